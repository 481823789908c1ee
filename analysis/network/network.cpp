// Stage `network` (issue 6): being written.
