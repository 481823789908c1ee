// Stage `friction` (issue 6): being written.
