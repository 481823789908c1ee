// Stage `cg` (issue 5): being written.
