#!/bin/sh
# Runs the worked example of docs/bring-your-camera.md as written: the first ```sh block after
# "## Worked example", in a scratch folder that holds the repository's scenes/ and build/skypol.
# usage: guide_example.sh SOURCE_DIR SKYPOL_BINARY
set -eu
src=$1
bin=$2
d=$(mktemp -d)
trap 'rm -rf "$d"' EXIT
mkdir -p "$d/build"
ln -s "$src/scenes" "$d/scenes"
ln -s "$bin" "$d/build/skypol"
awk '/^## Worked example/ {on = 1} on && /^```sh/ {block = 1; next} block && /^```/ {exit} block {print}' \
  "$src/docs/bring-your-camera.md" > "$d/example.sh"
test -s "$d/example.sh"
cd "$d"
sh -e example.sh > out.txt 2>&1 || { cat out.txt; exit 1; }
cat out.txt
# The import's estimates are the rendered stack's, printed without the truth.
grep -q "truth unknown" out.txt
build/skypol estimate -q out/camera/rendered.exr -m classic,great_circle --json > rendered.json
build/skypol estimate -q out/camera/capture.exr -m classic,great_circle --json > capture.json
a=$(grep -o '"heading_deg": [^,]*' rendered.json)
b=$(grep -o '"heading_deg": [^,]*' capture.json)
echo "rendered: $a"
echo "imported: $b"
test "$a" = "$b"
