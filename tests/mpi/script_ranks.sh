#!/bin/sh
# script_ranks.sh DEMLAB MPIEXEC NP: `mpirun -np NP demlab script.tcl` against `demlab
# script.tcl`. falling_bed.tcl gives the serial run's values (compare_runs.tcl) and VTK files
# (vtk_compare.py: pieces a rank under a .pvtp, read by VTK's own readers) and snapshots (drawn
# by rank 0 from every rank's elements, compared pixel by pixel); an error
# raised on every rank ends the run once with it; Ctrl-C sent to one rank stops every rank at
# the same step; one rank failing alone ends the run (aborted) rather than leaving the others
# waiting; the console is refused.
set -u
demlab=$1 mpiexec=$2 np=$3
here=$(cd "$(dirname "$0")" && pwd)
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
fail() { echo "script_ranks.sh: $*" >&2; exit 1; }

mkdir "$dir/serial" "$dir/ranks"
"$demlab" "$here/falling_bed.tcl" "$dir/serial" > "$dir/serial.txt" || fail "falling_bed.tcl failed alone"
"$mpiexec" -np "$np" "$demlab" "$here/falling_bed.tcl" "$dir/ranks" > "$dir/ranks.txt" ||
  fail "falling_bed.tcl failed on $np ranks"
"$demlab" "$here/compare_runs.tcl" "$dir/serial.txt" "$dir/ranks.txt" "$np" || fail "runs differ"
if [ "$np" -gt 1 ]; then
  /usr/bin/python3 "$here/vtk_compare.py" "$dir/serial/bed" "$dir/ranks/bed" || fail "the VTK files differ"
  /usr/bin/python3 "$here/vtk_compare.py" --series "$dir/serial/series" "$dir/ranks/series" ||
    fail "the VTK series differ"
  frames=""
  for f in bed.png tagged.png frames/frame_000000.png frames/frame_000001.png frames/frame_000002.png; do
    frames="$frames $dir/serial/$f $dir/ranks/$f"
  done
  # shellcheck disable=SC2086
  /usr/bin/python3 "$here/vtk_compare.py" --png $frames || fail "the snapshots differ"
  /usr/bin/python3 "$here/vtk_compare.py" --csv "$dir/serial/bed.csv" "$dir/ranks/bed.csv" ||
    fail "the CSV dumps differ"
  /usr/bin/python3 "$here/vtk_compare.py" --lammps "$dir/serial/bed.data" "$dir/ranks/bed.data" ||
    fail "the LAMMPS data files differ"
fi

# Checkpoints across rank counts: saved on np ranks (and alone), loaded alone and on np + 1
# ranks (np - 1 from 3), each going on as the saving run did.
ck() {  # ck RANKS MODE FILE OUT: checkpoint_bed.tcl on RANKS ranks (0: alone)
  if [ "$1" -eq 0 ]; then "$demlab" "$here/checkpoint_bed.tcl" "$2" "$3" > "$4"
  else "$mpiexec" -np "$1" "$demlab" "$here/checkpoint_bed.tcl" "$2" "$3" > "$4"; fi ||
    fail "checkpoint_bed.tcl $2 on $1 ranks failed"
}
other=$((np == 3 ? 2 : np + 1))
ck "$np" save "$dir/np.dcp" "$dir/ck_saved_np.txt"
ck 0 load "$dir/np.dcp" "$dir/ck_np_alone.txt"
ck "$other" load "$dir/np.dcp" "$dir/ck_np_other.txt"
ck 0 save "$dir/alone.dcp" "$dir/ck_saved_alone.txt"
ck "$np" load "$dir/alone.dcp" "$dir/ck_alone_np.txt"
same() {  # same SAVED LOADED NP: compare_runs.tcl's rule for NP ranks (1: bit for bit)
  "$demlab" "$here/compare_runs.tcl" "$dir/$1" "$dir/$2" "$3" 1e-5 || fail "checkpoint: $2 differs from $1"
}
same ck_saved_np.txt ck_np_alone.txt "$np"
same ck_saved_np.txt ck_np_other.txt 2
same ck_saved_alone.txt ck_alone_np.txt "$np"

[ "$np" -gt 1 ] || exit 0
"$mpiexec" -np "$np" "$demlab" "$here/unsupported_scene.tcl" > "$dir/out.txt" 2> "$dir/err.txt"
[ $? -eq 1 ] || fail "unsupported_scene.tcl: exit status not 1"
n=$(grep -c "which distributed runs do not support yet" "$dir/err.txt")
[ "$n" -eq 1 ] || { cat "$dir/err.txt" >&2; fail "unsupported_scene.tcl: the error printed $n times"; }

# Ctrl-C sent to one rank alone: every rank stops at the same step, and runs on.
mkdir "$dir/interrupted"
timeout 120 "$mpiexec" -np "$np" "$demlab" "$here/interrupted_rank.tcl" "$dir/interrupted" \
  > "$dir/out.txt" 2> "$dir/err.txt" || { cat "$dir/err.txt" >&2; fail "interrupted_rank.tcl: exit status $?"; }
first=$(head -n 1 "$dir/interrupted/rank0.txt")
case "$first" in
  "1 {DEMLAB INTERRUPTED} {step "*) ;;
  *) fail "interrupted_rank.tcl: rank 0 saw: $first" ;;
esac
r=0
while [ "$r" -lt "$np" ]; do
  [ "$(cat "$dir/interrupted/rank$r.txt")" = "$(printf '%s\nnext 0' "$first")" ] ||
    fail "interrupted_rank.tcl: rank $r saw $(cat "$dir/interrupted/rank$r.txt"), rank 0 $first"
  r=$((r + 1))
done
echo "interrupted_rank.tcl: every rank stopped alike: $first"

start=$(date +%s)
timeout 120 "$mpiexec" -np "$np" "$demlab" "$here/failing_rank.tcl" > "$dir/out.txt" 2> "$dir/err.txt"
status=$?
[ $status -ne 0 ] && [ $status -ne 124 ] || fail "failing_rank.tcl: exit status $status"
grep -q "the last rank fails alone" "$dir/err.txt" || { cat "$dir/err.txt" >&2; fail "failing_rank.tcl: no error"; }
grep -q "aborting the run" "$dir/err.txt" || { cat "$dir/err.txt" >&2; fail "failing_rank.tcl: not aborted"; }
echo "failing_rank.tcl: aborted after $(( $(date +%s) - start )) s"

"$mpiexec" -np "$np" "$demlab" < /dev/null > "$dir/out.txt" 2> "$dir/err.txt"
[ $? -eq 2 ] || fail "the console under mpirun: exit status not 2"
grep -q "under mpirun demlab runs a script" "$dir/err.txt" || fail "the console: no message"
echo "script_ranks.sh: $np ranks: all checks hold"
