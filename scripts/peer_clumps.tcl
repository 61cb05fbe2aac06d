# Rigid clumps (dumbbells) settling in a box: the demlab side of scripts/peer-clumps (which see).
# Arguments: n side height settle-steps timed-steps members-file
#
# A clump is two spheres of radius 1 mm whose centres are 1.5 mm apart (shape clump; its mass
# and inertia those of the union). The material's law is demlab's default, Hertz-Mindlin
# (Hertz normal, a tangential spring with history and Coulomb's limit, damping calibrated to
# the restitution), E = 5e6 Pa, nu = 0.3, e = 0.5, mu = 0.5, 2500 kg/m^3, against the five
# plane walls too (floor z = 0, sides x, y = 0 and side). The clumps are packed at random,
# turned at random, their bounding spheres (1.75 mm) apart and inside the box
# 0 < x, y < side, 0 < z < height; they settle under gravity for settle-steps steps of 1e-5 s
# (not timed), then run timed-steps steps.
#
# Prints one line on stdout: "cpu_seconds contacts": the CPU time (utime + stime of this
# process) of the timed steps, and `query contacts -count` after them (sphere-sphere points,
# one a touching member pair, and sphere-wall points). Writes the member spheres to
# members-file, a line "body x y z r" each, for bench/peer/clump_contacts.py.
lassign $argv count side height settle timed members
source [file join [file dirname [info script]] bench_common.tcl]
benchScene
wall add plane -point {0 0 0} -normal {0 0 1}
addSideWalls $side
# The dumbbell in units of its members' radius; -radius is its bounding radius, 1.75 mm, so the
# members come out at 1 mm.
set half 0.00075
pack random -region [list box {0 0 0} [list $side $side $height]] -radius 0.00175 -count $count \
    -seed 1 -shape clump -params {-0.75 0 0 1 0.75 0 0 1} -orientation random
sim timestep 1e-5
puts stderr "demlab: [sim info]"
sim run -steps $settle -quiet
puts stderr "demlab: after settling: [query energy]"
set c0 [cpuSeconds]
set report [sim run -steps $timed -quiet]
set cpu [expr {[cpuSeconds] - $c0}]
# The timed run's wall time per step by module (us), for the record.
set modules {}
dict for {m t} [dict get $report modules] {lappend modules [format "%s %.1f" $m [expr {$t * 1e6}]]}
puts stderr [format "demlab: timed run: %.1f us a step (wall), by module: %s; rebuilds %d" \
    [expr {[dict get $report per_step] * 1e6}] [join $modules ", "] [dict get $report rebuilds]]
set contacts [query contacts -count]
# The members: the clump's centre plus its orientation applied to (+-0.75 mm, 0, 0) (the first
# column of the rotation matrix of the quaternion {w x y z}).
set f [open $members w]
foreach id [element list] {
    lassign [dict get [element get $id] position] x y z
    lassign [dict get [element get $id] orientation] qw qx qy qz
    set ax [expr {$half * (1 - 2 * ($qy * $qy + $qz * $qz))}]
    set ay [expr {$half * 2 * ($qx * $qy + $qw * $qz)}]
    set az [expr {$half * 2 * ($qx * $qz - $qw * $qy)}]
    puts $f [format "%d %.12g %.12g %.12g 0.001" $id [expr {$x - $ax}] [expr {$y - $ay}] [expr {$z - $az}]]
    puts $f [format "%d %.12g %.12g %.12g 0.001" $id [expr {$x + $ax}] [expr {$y + $ay}] [expr {$z + $az}]]
}
close $f
puts [format "%.2f %d" $cpu $contacts]
