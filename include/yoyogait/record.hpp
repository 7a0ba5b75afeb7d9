/// @file record.hpp
/// @brief What the tables of the records (Estimate, Innovation, OnlineEstimate, OnlineConfig) have in
/// common: each row of a table declares one field (type, name, default, unit, doc); a struct's members
/// are generated from it, and so are the bindings' columns and the schema Python follows.
#pragma once

namespace yoyogait {

/// Which algorithms fill a field of Estimate with something of their own (see YOYOGAIT_ESTIMATE_FIELDS).
enum class FieldScope : unsigned char {
  kAll = 0,   ///< both
  kGait = 1,  ///< the gait filter only; the paper's value is a constant
};

/// One field of a record, for code that lists, documents or checks the records.
struct RecordField {
  const char* name;
  const char* type;  ///< "float", "bool", "uint8" (codes and counts)
  const char* unit;  ///< "" where the field has none
  const char* doc;
};

}  // namespace yoyogait

/// A struct member from a row of a record table (the scope, where a table has one, is ignored).
#define YOYOGAIT_RECORD_MEMBER(type, name, def, unit, scope, doc) type name = def;
