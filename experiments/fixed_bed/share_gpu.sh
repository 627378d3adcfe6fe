#!/usr/bin/env bash
# How many fixed beds one GPU runs at once: N copies of one stopped bed (a fixed_bed.py run
# folder with checkpoints) resumed together for SECONDS of simulated time, first as plain
# processes (the GPU takes turns between them), then under MPS (NVIDIA's Multi-Process Service:
# their kernels share the SMs). Prints each batch's steady steps a second, each copy's and the
# sum, the summary's cuda_graphs, and each failed copy's last words.
#
# usage: experiments/fixed_bed/share_gpu.sh TALUS RUN_DIR SECONDS N [N ...]
#   e.g. share_gpu.sh build-cuda/talus runs/fixed_bed-16-1 0.03 1 2 4 8
# RUN_DIR's scene.yaml must stay where the checkpoint names it: the copies are resumed from
# copies of RUN_DIR under $TMPDIR (default /tmp), and removed at the end. Needs python3 and, for
# the MPS half, nvidia-cuda-mps-control (skipped with a line when it does not start).
set -u
if (( $# < 4 )); then
  sed -n '2,12p' "$0" >&2
  exit 2
fi
talus=$(realpath "$1") src=$(realpath "$2") span=$3
shift 3
[[ -x $talus ]] || { echo "share_gpu.sh: $talus: not an executable" >&2; exit 2; }
[[ -f $src/run.json && -d $src/run/checkpoints ]] ||
  { echo "share_gpu.sh: $src: no run.json and run/checkpoints (a fixed_bed.py run folder)" >&2; exit 2; }
end=$(python3 -c "import json; r=json.load(open('$src/run.json')); print(r['sitting_steps'][-1]['step'] * r['time_step_s'] + $span)") ||
  { echo "share_gpu.sh: $src/run.json: no sitting_steps to resume from" >&2; exit 2; }
work=$(mktemp -d "${TMPDIR:-/tmp}/share_gpu.XXXXXX")
trap 'rm -rf "$work"' EXIT
name=$(basename "$src")

batch() {  # batch TAG N
  local tag=$1 n=$2 k
  for k in $(seq "$n"); do mkdir -p "$work/$k" && rm -rf "$work/$k/$name" && cp -a "$src" "$work/$k/"; done
  local t0=$(date +%s.%N)
  for k in $(seq "$n"); do
    "$talus" run --resume "$work/$k/$name/run/checkpoints" --end "$end" --quiet \
      > "$work/$k.json" 2> "$work/$k.err" &
  done
  wait
  python3 - "$tag" "$n" "$t0" "$work" <<'PY'
import json, sys, time
tag, n, t0, work = sys.argv[1], int(sys.argv[2]), float(sys.argv[3]), sys.argv[4]
rates, graphs = [], None
for k in range(1, n + 1):
    try:
        s = json.load(open(f"{work}/{k}.json"))
        rates.append(s["steady"]["steps"] / s["steady"]["seconds"])
        graphs = s.get("cuda_graphs")
    except (OSError, ValueError, KeyError):
        print(f"{tag} N={n} copy {k} failed: " + open(f"{work}/{k}.err").read()[-300:].strip())
print(f"{tag} N={n}: {sum(rates):.0f} steps/s in all, each "
      + ", ".join(f"{r:.0f}" for r in rates) + f"; {time.time() - t0:.1f} s wall; graphs {graphs}")
PY
}

for n in "$@"; do batch plain "$n"; done
export CUDA_MPS_PIPE_DIRECTORY=$work/mps-pipe CUDA_MPS_LOG_DIRECTORY=$work/mps-log
mkdir -p "$CUDA_MPS_PIPE_DIRECTORY" "$CUDA_MPS_LOG_DIRECTORY"
if command -v nvidia-cuda-mps-control > /dev/null && nvidia-cuda-mps-control -d; then
  for n in "$@"; do batch mps "$n"; done
  echo quit | nvidia-cuda-mps-control
  grep -h "fatal\|sticky" "$CUDA_MPS_LOG_DIRECTORY"/server.log 2>/dev/null | sed 's/^/mps server: /'
else
  echo "share_gpu.sh: MPS did not start: the plain batches only"
fi
