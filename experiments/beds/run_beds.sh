#!/usr/bin/env bash
# Runs the poured-bed cases (experiments/beds/README.md): writes the scenes with make_scenes.py,
# runs each with `talus run`, and records per case its exit status and wall time in
# OUT/runs.csv. A failing case (the energy watchdog stopping a paper-law run, a refusal) does not
# stop the others: its probes up to the stop are still the data.
#
#   experiments/beds/run_beds.sh [OUT]        (OUT default: $BEDS_OUT or beds-out)
#
# Environment (defaults in brackets):
#   TALUS            the talus binary [build-gpu/talus]
#   BEDS_BACKEND     --backend of every run [cuda]
#   BEDS_PARTICLES   particles per bed, rounded up to full lattice layers [8640]
#   BEDS_END         simulated time, s [1.0]
#   BEDS_DT          the fixed time step of the main set, s [1e-5]
#   BEDS_AUTO        the default law at the advised step (step: auto, 0.2 dt_crit) as well: 'all'
#                    shapes, 'refused' only those whose dt_crit is below BEDS_DT, 'none' [all]
#   BEDS_SHAPES      comma-separated subset of the shapes [all seven]
#   BEDS_LAWS        comma-separated subset of volume,volume_paper [both]
#   BEDS_CASES       extended regex: run only the case names it matches [all]
#   BEDS_SKIP_DONE   1: skip cases that runs.csv already records as finished (exit 0) [0]
#   BEDS_TIMEOUT     seconds per case (SIGTERM: talus stops at a step boundary, exit 143, its
#                    outputs so far kept) [none]
#   BEDS_TALUS_ARGS  more `talus run` options, e.g. '--threads 2' []
#   PYTHON           Python 3 for make_scenes.py [python3]
#
# Quick check: BEDS_PARTICLES=500 BEDS_END=0.2 experiments/beds/run_beds.sh beds-small
set -u

here=$(cd "$(dirname "$0")" && pwd)
talus=${TALUS:-build-gpu/talus}
out=${1:-${BEDS_OUT:-beds-out}}
backend=${BEDS_BACKEND:-cuda}
particles=${BEDS_PARTICLES:-8640}
end=${BEDS_END:-1.0}
dt=${BEDS_DT:-1e-5}
auto=${BEDS_AUTO:-all}
cases_re=${BEDS_CASES:-.}
python=${PYTHON:-python3}

if [[ ! -x $talus ]]; then
  echo "run_beds.sh: no talus binary at '$talus' (set TALUS)" >&2
  exit 2
fi
case $auto in refused | all | none) ;; *)
  echo "run_beds.sh: BEDS_AUTO must be all, refused or none, got '$auto'" >&2
  exit 2
  ;;
esac

subset=()
[[ -n ${BEDS_SHAPES:-} ]] && subset+=(--shapes "$BEDS_SHAPES")
[[ -n ${BEDS_LAWS:-} ]] && subset+=(--laws "$BEDS_LAWS")
common=(--particles "$particles" --end "$end" "${subset[@]}")

# The main set at the fixed step; the advised-step set at 0.2 dt_crit. make_scenes.py asks talus
# for each case's dt_crit (a step of 8 particles on the host), listed in cases.txt.
# Scenes of earlier subsets stay (analyze.py reads them); each set's cases.txt lists this run's.
rm -f "$out/scenes/cases.txt" "$out/scenes_auto/cases.txt"
"$python" "$here/make_scenes.py" "$out/scenes" "${common[@]}" --dt "$dt" --talus "$talus" || exit 2
if [[ $auto != none && ,${BEDS_LAWS:-volume}, == *,volume,* ]]; then
  where=()
  [[ $auto == refused ]] && where=(--where-above "$dt")
  "$python" "$here/make_scenes.py" "$out/scenes_auto" "${common[@]}" --laws volume --auto \
    --talus "$talus" "${where[@]}" || exit 2
fi

csv=$out/runs.csv
header=case,shape,law,dt,particles,backend,exit_status,wall_seconds,finished_at
[[ -f $csv ]] || echo "$header" >"$csv"

# Has runs.csv a finished (exit 0) row for this case, on its last row for it?
finished() {
  awk -F, -v c="$1" '$1 == c { s = $7 } END { exit !(s == "0") }' "$csv"
}

failures=0
for dir in "$out/scenes" "$out/scenes_auto"; do
  [[ -f $dir/cases.txt ]] || continue
  # The fixed-step set runs above the advisor's limit where it must: the paper's law everywhere
  # (the "before") and the default law for any shape whose dt_crit is below BEDS_DT. The ratio
  # goes to the run's summary or its error message. The advised-step set never needs it.
  flags=()
  [[ $dir == "$out/scenes" ]] && flags=(--allow-unstable-step)
  while read -r name shape law step _; do
    [[ $name == \#* || -z $name ]] && continue
    [[ $name =~ $cases_re ]] || continue
    if [[ ${BEDS_SKIP_DONE:-0} == 1 ]] && finished "$name"; then
      echo "run_beds.sh: $name already finished; skipped" >&2
      continue
    fi
    run=$out/runs/$name
    rm -rf "$run" && mkdir -p "$run"
    count=$(sed -n 's/^# [^:]*: \([0-9]*\) particles.*/\1/p' "$dir/$name.yaml")
    limit=()
    [[ -n ${BEDS_TIMEOUT:-} ]] && limit=(timeout --preserve-status --signal=TERM "$BEDS_TIMEOUT")
    echo "run_beds.sh: $name ($count particles, dt $step s) ..." >&2
    start=$(date +%s.%N)
    # shellcheck disable=SC2086  # BEDS_TALUS_ARGS is a list of words
    "${limit[@]}" "$talus" run "$dir/$name.yaml" --backend "$backend" --output "$run" --quiet \
      "${flags[@]}" ${BEDS_TALUS_ARGS:-} >"$run/summary.json" 2>"$run/stderr.log"
    status=$?
    wall=$(awk -v a="$start" -v b="$(date +%s.%N)" 'BEGIN { printf "%.1f", b - a }')
    echo "$name,$shape,$law,$step,$count,$backend,$status,$wall,$(date -u +%FT%TZ)" >>"$csv"
    if [[ $status != 0 ]]; then
      failures=$((failures + 1))
      echo "run_beds.sh: $name exited with $status after $wall s:" \
        "$(tail -c 400 "$run/stderr.log")" >&2
    else
      echo "run_beds.sh: $name done in $wall s" >&2
    fi
  done <"$dir/cases.txt"
done
echo "run_beds.sh: done; $failures case(s) did not finish; table: $csv" >&2
echo "run_beds.sh: next: $python $here/analyze.py $out --talus $talus" >&2
