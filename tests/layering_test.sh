#!/bin/sh
# The engine's folders are layers (docs/engine.md, "Code layout"): a file of
# sim/<folder>/ includes only its own folder and folders listed before it.
#   layering_test.sh SIM_DIR FOLDER...   (the folders bottom up, as sim/CMakeLists.txt lists them)
# Prints every include that runs back up, and fails if there is one.
sim=$1
shift
order="$*"
rank() { i=0; for f in $order; do [ "$f" = "$1" ] && { echo $i; return; }; i=$((i + 1)); done; echo -1; }
bad=0
for dir in "$sim"/*/; do
  from=$(basename "$dir")
  r_from=$(rank "$from")
  [ "$r_from" -ge 0 ] || { echo "sim/$from/: a folder the layer list does not name"; bad=1; continue; }
  for file in "$dir"*; do
    for to in $(sed -n 's|^#include "\([a-z_]*\)/.*|\1|p' "$file" | sort -u); do
      r_to=$(rank "$to")
      [ "$r_to" -ge 0 ] || continue
      if [ "$r_to" -gt "$r_from" ]; then
        echo "$(basename "$file") in sim/$from/ includes $to/, a layer above it"
        bad=1
      fi
    done
  done
done
[ $bad -eq 0 ] && echo "sim/: $(echo $order | wc -w) layers, no include runs back up"
exit $bad
