"""Where the real recordings are: ../shared/datasets beside the project, or $YOYOGAIT_DATASETS.

Its own module (not conftest) so that test modules can list the files at collection time without
importing a conftest by name (several folders have one)."""

from __future__ import annotations

import os
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
DATASETS = Path(os.environ.get("YOYOGAIT_DATASETS", ROOT.parent / "shared" / "datasets"))
