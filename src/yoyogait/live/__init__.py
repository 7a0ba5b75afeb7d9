"""Live input and output: motion-capture frames over Lab Streaming Layer (LSL), estimates back out.

* :mod:`.layout`: the marker stream's channels (``<point>_x/_y/_z`` in metres, plus ``time_s``)
  and how a stream from another system is read (labels, units, up axis).
* :mod:`.replay`: a recording played into an LSL marker stream at its capture rate.
* :mod:`.live`: a marker stream through the online estimator into an estimate stream.

pylsl is an optional dependency (``pip install 'yoyogait[live]'``), imported where it is used.
Channel layouts and behaviour are documented in docs/live.md.
"""

from __future__ import annotations
