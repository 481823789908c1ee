// Stage `spectrum` (issue 4): being written.
