#!/bin/sh
# shellcheck disable=SC2086 # $opts: several words, split on purpose
# ctest `parallel_ranks` (label parallel): `mpirun -np N talus run` on the host backend
# (docs/parallel.md) gives the trajectories of one process to the bit, whatever N:
#  - the drum (tests/parallel/scenes/drum.yaml: particles cross the ranks' boxes back and forth,
#    a moving wall, friction histories) on 1, 2, 3 and 4 ranks: every trajectory frame identical,
#    byte for byte; the probes' contact counts identical and their energies and wall forces
#    within 1e-9 of each column's largest magnitude (the same terms summed over ranks in another
#    order differ by rounding only: about 1e-14 relative here; a contact missed or counted twice
#    changes them by more than 1e-4); the summary's exchange seconds hold the rebuild vote's
#    and the rebuilds' as parts;
#  - the silo (scenes/silo.yaml: a feed whose region the ranks' boxes cut, removal below the
#    outlet) on 1 and 3 ranks: the frames identical, and the particles and removals counted alike;
#    the boxes were cut again (rebalanced) as the particles gathered at the bottom;
#  - a restart from 2 ranks into 3: the drum stopped at 0.1 s on 2 ranks and resumed on 3 from
#    its checkpoint at 0.075 s gives the frames of the uninterrupted one-process run (the states
#    gathered and broadcast in rounds of 4096 bytes, TALUS_MPI_MESSAGE_BYTES);
#  - a run stopped by --stop-after on 2 ranks exits with 75 and resumes to those frames too;
#  - any command but run on several ranks is refused with a message.
# BACKEND cuda (ctest `parallel_ranks_gpu`, label gpu): the same on the CUDA backend, every rank
# on the GPU of its local rank (all on one GPU here), against the one-process CUDA run; skipped
# where talus has no CUDA or no GPU is usable.
# Skipped (exit 77) where mpirun is missing or talus was built without MPI.
# usage: run_ranks.sh TALUS SOURCE_DIR WORK_DIR [BACKEND (cpu)]
set -u
talus=$1 source=$2 work=$3 backend=${4:-cpu}
scenes=$source/tests/parallel/scenes
rm -rf "$work" && mkdir -p "$work" || exit 1
name=parallel_ranks
test "$backend" = cpu || name=parallel_ranks_gpu
fail() { echo "$name: $*"; exit 1; }
opts="--threads 1 --backend $backend"
if [ "$backend" = cuda ]; then
  "$talus" run "$scenes/drum.yaml" $opts --quiet --end 0.0001 --output "$work/gpu-probe" \
    > /dev/null 2> "$work/gpu-probe.err" || {
    echo "SKIPPED: no CUDA backend here: $(cat "$work/gpu-probe.err")"; exit 77; }
fi
command -v mpirun > /dev/null || { echo "SKIPPED: no mpirun (scripts/setup installs Open MPI)"; exit 77; }
# Open MPI refuses root without these; CI's two cores run three ranks oversubscribed.
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
# A rank waiting for another yields its core rather than spin (more ranks than cores).
export OMPI_MCA_mpi_yield_when_idle=1
mpi() { n=$1; shift; mpirun -np "$n" "$@"; }

# A decomposed run needs a talus built with MPI: one without it runs each rank alone, and its
# ranks would all write the outputs; the summary says how many ranks ran.
mpi 2 "$talus" run "$scenes/drum.yaml" $opts --quiet --end 0.0001 \
  --output "$work/probe" > "$work/probe.json" 2> "$work/probe.err"
if ! grep -q '"ranks": 2' "$work/probe.json"; then
  echo "SKIPPED: talus was built without MPI (no \"ranks\": 2 in its summary)"; exit 77
fi

same_frames() {  # DIR_A DIR_B: every trajectory frame of A in B, byte for byte
  count=0
  for f in "$1"/frames/trajectory_*.csv; do
    cmp -s "$f" "$2/frames/$(basename "$f")" || fail "$2: $(basename "$f") differs from $1's"
    count=$((count + 1))
  done
  test "$count" -ge 5 || fail "$1: only $count frames"
  echo "$name: $2: $count frames identical to $1's"
}
exchange_parts() {  # SUMMARY: the exchange's vote and rebuild seconds are parts of it
  # (top-level keys, two spaces in; the steady part's are deeper), the rebuilds taking some time:
  # the drum's list is rebuilt dozens of times.
  /usr/bin/awk -v f="$1" '
    /^  "exchange_seconds"/ { total = $2 + 0; seen++ }
    /^  "exchange_vote_seconds"/ { vote = $2 + 0; seen++ }
    /^  "exchange_rebuild_seconds"/ { rebuild = $2 + 0; seen++ }
    END {
      if (seen != 3) { print f ": no exchange seconds with their parts"; exit 1 }
      if (!(rebuild > 0) || vote < 0 || vote + rebuild > total) {
        printf "%s: exchange %g s, vote %g s, rebuild %g s\n", f, total, vote, rebuild; exit 1
      }
    }' "$1" || fail "the exchange's parts"
}
close_probes() {  # A B: contact counts equal, the rest within 1e-9 of each column's scale
  /usr/bin/awk -F, -v a="$1" -v b="$2" '
    FNR == 1 { if (NR == 1) header = $0; else if ($0 != header) bad = "headers differ"; next }
    NR == FNR { for (c = 1; c <= NF; ++c) v[FNR, c] = $c; rows = FNR; next }
    {
      if (FNR > rows) { bad = "more rows"; exit }
      for (c = 1; c <= NF; ++c) {
        d = $c - v[FNR, c]; if (d < 0) d = -d
        m = $c < 0 ? -$c : $c; if (m > scale[c]) scale[c] = m
        if (d > diff[c]) diff[c] = d
      }
      n = NF
    }
    END {
      if (bad != "") { print bad; exit 1 }
      split(header, name, ",")
      for (c = 1; c <= n; ++c) {
        limit = name[c] ~ /contact_count/ ? 0 : 1e-9 * scale[c]
        if (diff[c] > limit) { printf "%s: off by %g (limit %g)\n", name[c], diff[c], limit; exit 1 }
      }
    }' "$1" "$2" || fail "$2 against $1"
}
"$talus" run "$scenes/drum.yaml" $opts --quiet --output "$work/drum-1" \
  > "$work/drum-1.json" || fail "the one-process drum exited with $?"
for n in 2 3 4; do
  mpi "$n" "$talus" run "$scenes/drum.yaml" $opts --quiet --output "$work/drum-$n" \
    > "$work/drum-$n.json" 2> "$work/drum-$n.err" || fail "the drum on $n ranks exited with $?: $(cat "$work/drum-$n.err")"
  grep -q "\"ranks\": $n" "$work/drum-$n.json" || fail "the drum's summary does not say $n ranks"
  same_frames "$work/drum-1" "$work/drum-$n"
  close_probes "$work/drum-1/probes.csv" "$work/drum-$n/probes.csv"
  exchange_parts "$work/drum-$n.json"
done
"$talus" run "$scenes/silo.yaml" $opts --quiet --output "$work/silo-1" \
  > "$work/silo-1.json" || fail "the one-process silo exited with $?"
mpi 3 "$talus" run "$scenes/silo.yaml" $opts --quiet --output "$work/silo-3" \
  > "$work/silo-3.json" 2> "$work/silo-3.err" || fail "the silo on 3 ranks exited with $?: $(cat "$work/silo-3.err")"
same_frames "$work/silo-1" "$work/silo-3"
for key in particles removed_particles; do
  one=$(grep "\"$key\"" "$work/silo-1.json") three=$(grep "\"$key\"" "$work/silo-3.json")
  test "$one" = "$three" || fail "silo: $one on one process, $three on 3 ranks"
done
grep -q '"removed_particles": [1-9]' "$work/silo-1.json" || fail "silo: no particle removed"
# The pour collapses to the bottom: the boxes must have been cut again (Scene::rebalance, 1.25).
grep -q '"rebalances": [1-9]' "$work/silo-3.json" || fail "silo: the boxes were never cut again"
# The restart's ranks gather and broadcast whole states in rounds of 4096 bytes (a state over
# 1 GiB, 2e7 particles, takes several rounds; the drum's 30 kB take a few here).
TALUS_MPI_MESSAGE_BYTES=4096 mpi 2 "$talus" run "$scenes/drum.yaml" $opts --quiet --end 0.1 \
  --output "$work/restart" > "$work/restart-2.json" 2> "$work/restart-2.err" ||
  fail "the drum to 0.1 s on 2 ranks exited with $?: $(cat "$work/restart-2.err")"
TALUS_MPI_MESSAGE_BYTES=4096 mpi 3 "$talus" run --resume "$work/restart/checkpoints" $opts --quiet \
  > "$work/restart-3.json" 2> "$work/restart-3.err" ||
  fail "the resumed drum on 3 ranks exited with $?: $(cat "$work/restart-3.err")"
grep -q '"ranks": 3' "$work/restart-3.json" || fail "the resumed run does not say 3 ranks"
same_frames "$work/drum-1" "$work/restart"
# --stop-after under mpirun: rank 0 stops every rank at one step with a checkpoint (exit 75; a
# deadline passed before the first step puts the stop at step 0 on any machine), and the run
# resumed on 2 ranks gives the one-process frames.
mpi 2 "$talus" run "$scenes/drum.yaml" $opts --quiet --stop-after 1e-6 --output "$work/stopped" \
  > "$work/stopped-2.json" 2> "$work/stopped-2.err"
status=$?
test $status = 75 || fail "the drum stopped by --stop-after on 2 ranks exited with $status, not 75: $(cat "$work/stopped-2.err")"
grep -q "run stopped after --stop-after 1e-06 s at step 0 " "$work/stopped-2.err" ||
  fail "the stopped drum's message: $(cat "$work/stopped-2.err")"
mpi 2 "$talus" run --resume "$work/stopped/checkpoints" $opts --quiet \
  > "$work/stopped-resumed.json" 2> "$work/stopped-resumed.err" ||
  fail "the stopped drum resumed on 2 ranks exited with $?: $(cat "$work/stopped-resumed.err")"
same_frames "$work/drum-1" "$work/stopped"

# Threads: 2 ranks of --threads C each (C this machine's cores) start 2C threads on C cores, which
# rank 0 says once (also with --quiet) naming the share to give; --threads C/2 (or none) is not
# oversubscribed and says nothing. The host backend: the warning is the command's, not the step's.
cores=$(nproc)
if test "$cores" -ge 2; then  # --threads 1 is never told (ranks beyond the cores are not threads)
  mpi 2 "$talus" run "$scenes/drum.yaml" --backend cpu --threads "$cores" --quiet --end 0.0001 \
    --output "$work/threads-over" > /dev/null 2> "$work/threads-over.err" ||
    fail "the drum on 2 ranks of $cores threads exited with $?: $(cat "$work/threads-over.err")"
  test "$(grep -c "2 ranks on this node with --threads $cores each start $((2 * cores)) threads on its $cores cores.*give at most $((cores / 2))\$" "$work/threads-over.err")" = 1 ||
    fail "2 ranks of $cores threads on $cores cores, not one warning: $(cat "$work/threads-over.err")"
fi
share=$((cores / 2)); test "$share" -ge 1 || share=1
mpi 2 "$talus" run "$scenes/drum.yaml" --backend cpu --threads "$share" --quiet --end 0.0001 \
  --output "$work/threads-share" > /dev/null 2> "$work/threads-share.err" ||
  fail "the drum on 2 ranks of $share threads exited with $?: $(cat "$work/threads-share.err")"
if test $((2 * share)) -le "$cores" && grep -q "threads on its" "$work/threads-share.err"; then
  fail "2 ranks of $share threads on $cores cores warned: $(cat "$work/threads-share.err")"
fi

mpi 2 "$talus" shape cube:0.01 > "$work/shape.out" 2> "$work/shape.err" &&
  fail "talus shape on 2 ranks was not refused"
grep -q "only 'talus run' runs on several ranks" "$work/shape.err" ||
  fail "talus shape on 2 ranks: $(cat "$work/shape.err")"
echo "$name: passed"
