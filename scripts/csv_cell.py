"""Reads one numeric cell of a DEMLink CSV output.

DEMLink writes a value that does not exist (an empty region's mean velocity, a tracked
particle not yet present, a quantity not yet sampled) as an EMPTY cell, never as the
text "nan" or "inf" (core/include/demlink/core/output/csv_table.hpp). The scripts read
such a cell as missing: NaN in memory, to be skipped or reported by the caller.
"""

import math


def cell_number(text):
    """The number in `text`; NaN (missing) for an empty cell. Raises ValueError for any
    other text that is not a finite number, naming it."""
    stripped = text.strip()
    if not stripped:
        return math.nan
    value = float(stripped)
    if not math.isfinite(value):
        raise ValueError(f"'{text}' is not a finite number (a missing value is an empty cell)")
    return value


def is_missing(value):
    """True for what cell_number returns for an empty cell."""
    return math.isnan(value)
