# Boxes (convex polyhedra) settling in a box: the demlab side of scripts/peer-polyhedra (which
# see). Arguments: n side height settle-steps timed-steps
#
# A box is 4 x 3 x 2 mm (shape polyhedron, its 8 corners; half extents 2, 1.5 and 1 mm). The
# material's law is demlab's default, Hertz-Mindlin applied at each contact point (a face
# contact has up to 4 points, each with its own depth; the Hertz radius the volume-equivalent
# sphere's, 1.789 mm), damping calibrated to the restitution: E = 5e6 Pa, nu = 0.3, e = 0.5,
# mu = 0.5, 2500 kg/m^3, against the five plane walls too (floor z = 0, sides x, y = 0 and
# side). A box resting face down (4 x 3) on the floor sinks 0.966 um. The boxes are packed at
# random, turned at random, their bounding spheres (the half diagonal, 2.693 mm) apart and
# inside the box 0 < x, y < side, 0 < z < height; they settle under gravity for settle-steps
# steps of 1e-5 s (not timed), then run timed-steps steps.
#
# Prints one line on stdout: "cpu_seconds points pairs wall_pairs zmean ztop": the CPU time
# (utime + stime of this process) of the timed steps; after them `query contacts -count` (contact
# points), the contacting pairs (distinct box-box pairs plus distinct box-wall pairs, from
# `query contacts`) and of those the box-wall pairs; the mean height of the box centres and the
# highest corner (m).
lassign $argv count side height settle timed
source [file join [file dirname [info script]] bench_common.tcl]
benchScene
wall add plane -point {0 0 0} -normal {0 0 1}
addSideWalls $side
# The box's corners; -radius is its bounding radius, the half diagonal, so it keeps its size.
set hx 0.002
set hy 0.0015
set hz 0.001
set corners {}
foreach z [list -$hz $hz] {
    foreach y [list -$hy $hy] {
        foreach x [list -$hx $hx] { lappend corners $x $y $z }
    }
}
set bound [expr {sqrt($hx * $hx + $hy * $hy + $hz * $hz)}]
pack random -region [list box {0 0 0} [list $side $side $height]] -radius $bound -count $count \
    -seed 1 -shape polyhedron -params $corners -orientation random
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
set points [query contacts -count]
# Contacting pairs: each box-box pair and each box-wall pair once, however many points it has.
set pairs [dict create]
set wallPairs 0
foreach c [query contacts] {
    set a [dict get $c a]
    set b [dict get $c b]
    if {$b ne ""} {
        set key [expr {$a < $b ? "$a $b" : "$b $a"}]
    } else {
        set key "$a w[dict get $c wall]"
    }
    if {![dict exists $pairs $key]} {
        dict set pairs $key 1
        if {$b eq ""} { incr wallPairs }
    }
}
# The bed: the mean centre height and the highest corner (the centre plus the half extents along
# the third row of the rotation matrix of the quaternion {w x y z}).
set zsum 0.0
set ztop 0.0
foreach id [element list] {
    set z [lindex [dict get [element get $id] position] 2]
    lassign [dict get [element get $id] orientation] qw qx qy qz
    set top [expr {$z + $hx * abs(2 * ($qx * $qz - $qw * $qy)) + $hy * abs(2 * ($qy * $qz + $qw * $qx))
                   + $hz * abs(1 - 2 * ($qx * $qx + $qy * $qy))}]
    set zsum [expr {$zsum + $z}]
    if {$top > $ztop} { set ztop $top }
}
puts [format "%.2f %d %d %d %.6g %.6g" $cpu $points [dict size $pairs] $wallPairs \
    [expr {$zsum / [llength [element list]]}] $ztop]
