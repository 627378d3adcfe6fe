#!/bin/bash
# Host-backend decomposition on the GPU machine's CPU cores: the hopper, 8,000 steps
# (experiments/scaling/results/hopper-16-cores/README.md). Run from the repository root, OUT set.
set -u
export LD_LIBRARY_PATH=$PWD/build-cuda/lib OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
t=build-cuda/talus
scene=benchmarks/scenes/hopper.yaml
end=0.16
rm -rf /tmp/hs-*; mkdir -p "$OUT/hs"
lscpu | grep -E "Model name|^CPU\(s\)|Thread|Core" > "$OUT"/hs/cpu.txt
cat build-cuda/commit > "$OUT"/hs/commit.txt
run() {  # name ranks threads
  local name=$1 n=$2 th=$3
  if [ "$n" = 0 ]; then
    $t run $scene --backend cpu --threads "$th" --quiet --end $end --output /tmp/hs-"$name" > "$OUT"/hs/"$name".json 2> "$OUT"/hs/"$name".err
  else
    mpirun --bind-to none -np "$n" $t run $scene --backend cpu --threads "$th" --quiet --end $end --output /tmp/hs-"$name" > "$OUT"/hs/"$name".json 2> "$OUT"/hs/"$name".err
  fi
  echo "$name rc=$? $(grep -E '"(wall_seconds|exchange_seconds|rebalances|ranks)"' "$OUT"/hs/"$name".json | tr -d '\n ')"
}
run p16 0 16
run r2t8 2 8
run r4t4 4 4
run r8t2 8 2
run r16t1 16 1
python3 - <<'PY'
import glob, os
ref = sorted(glob.glob("/tmp/hs-p16/frames/trajectory_*.csv"))
def data(path):
    return {"text": open(path, "rb").read()}
for name in ["r2t8", "r4t4", "r8t2", "r16t1"]:
    differ = 0
    for r in ref:
        a, b = data(r), data(os.path.join(f"/tmp/hs-{name}/frames", os.path.basename(r)))
        same = a.keys() == b.keys() and all(a[k] == b[k] for k in a)
        differ += 0 if same else 1
    print(f"{name}: {differ} of {len(ref)} frames differ from p16's (byte for byte)")
PY
tar czf "$OUT"/hs.tar.gz -C "$OUT" hs && rm -rf "$OUT"/hs
