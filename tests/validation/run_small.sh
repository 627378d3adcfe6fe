#!/bin/sh
# ctest `validation_small` (label validation): the small version of every validation case on the
# host backend through `talus validate`, which must pass; the committed scene of the impact case
# must be the one its checker writes; where Debian's matplotlib is installed, each case's figure
# is drawn; and a case made to fail (free_fall_drag with a tolerance of 1e-12, far below the
# integrator's error) makes `talus validate` exit 1 and record the failure.
# usage: run_small.sh TALUS SOURCE_DIR WORK_DIR
set -u
talus=$1 source=$2 work=$3
rm -rf "$work" && mkdir -p "$work" || exit 1
fail() { echo "validation_small: $*"; exit 1; }

"$talus" validate --backend cpu --output "$work/small" > "$work/small.json" ||
  fail "talus validate exited with $? (see $work/small/validation-summary.md)"
grep -q '"passed": true' "$work/small.json" || fail "the results do not say passed"
cmp "$work/small/cylinder_wall_impact/scene.yaml" "$source/validation/cylinder_wall_impact/scene.yaml" ||
  fail "validation/cylinder_wall_impact/scene.yaml is not the scene its checker writes; copy $work/small/cylinder_wall_impact/scene.yaml over it"
if /usr/bin/python3 -c 'import matplotlib' 2> /dev/null; then
  for case in free_fall_drag cylinder_wall_impact mesh_resolution dodecahedron_packing \
    rotating_drum gravity_packing hopper_flow; do
    test -s "$work/small/$case/figure.png" || fail "no figure for $case: $(cat "$work/small/$case/figure.log")"
  done
else
  echo "validation_small: no /usr/bin/python3 with matplotlib: figures not checked"
fi

mkdir -p "$work/strict" && cp -r "$source/validation/free_fall_drag" "$work/strict/" || exit 1
sed 's/relative: 1.0e-3/relative: 1.0e-12/' "$source/validation/free_fall_drag/expected.yaml" \
  > "$work/strict/free_fall_drag/expected.yaml"
"$talus" validate --quiet --backend cpu --cases "$work/strict" --output "$work/strict-out" \
  free_fall_drag > "$work/strict.json"
status=$?
test "$status" = 1 || fail "a failing case: exit status $status, expected 1"
grep -q '"passed": false' "$work/strict.json" || fail "a failing case: the results do not say so"
grep -q '"verdict": "fail"' "$work/strict.json" || fail "a failing case: no check failed"
echo "validation_small: passed"
