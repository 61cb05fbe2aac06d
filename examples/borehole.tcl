# Borehole breakout (the thesis's figure 1-11), 2D: a square block of the bonded rock of
# examples/rock.tcl (demlab::sample, its four walls kept) with a circular hole drilled in its
# centre (the elements whose centre lies in it removed, their bonds with them), then loaded to
# an anisotropic far-field stress by its right and top walls under servo control (wall servo;
# the left and bottom ones stay): S1 across the x faces, S3 < S1 across the y faces. By Kirsch's solution the hoop stress on the hole's wall
# is S1 + S3 - 2 (S1 - S3) cos 2 theta (theta from x): largest, 3 S1 - S3, where the wall is
# crossed by the y axis, so the rock breaks out on the two sides of the hole in the direction of
# the least compressive stress S3, perpendicular to S1; with S3 = S1 / 3 (the defaults, 60 and
# 20 MPa) the hoop stress is nowhere tensile. The script measures where: the
# histogram of the angles (folded to [0, 90] degrees from the x axis) of the broken bonds
# within 2.5 hole radii of the centre, written as a CSV table, and the share of them within 30
# degrees of the y axis (a uniform spread would put a third there). With -frames DIR it writes
# PNG frames of the block coloured by each element's broken bonds.
#
#   build/demlab examples/borehole.tcl ?file.csv? ?-frames DIR? ?-s1 Pa? ?-s3 Pa? ?-side m?
#                                      ?-hole m? ?-seed n?
#
# -side, -hole: the block's side (default 12 mm, about 140 discs) and the hole's radius
# (1.8 mm). -short is accepted and changes nothing: the test suite's form is the default. A
# larger block (-side 0.024 -hole 0.003, about 540 discs) trips the watchdog's energy check
# during the elastic loading (the ledger's balance grows by half its scale; seeds 1 and 2),
# which is not explained yet.

source [file join [file dirname [info script]] rock.tcl]

array set opt {-short 0 -frames {} -s1 {} -s3 {} -hole {} -side {} -seed 1 -csv borehole.csv}
rock::parseArgs opt $argv
set L [expr {$opt(-side) ne {} ? $opt(-side) : 0.012}]   ;# the block's side, m
set a [expr {$opt(-hole) ne {} ? $opt(-hole) : 0.0018}]   ;# the hole's radius, m
set S1 [expr {$opt(-s1) ne {} ? $opt(-s1) : 6e7}]
set S3 [expr {$opt(-s3) ne {} ? $opt(-s3) : 2e7}]

rock::scene 2
rock::cement
set made [rock::sample [list box {0 0} [list $L $L]] -seed $opt(-seed) -keepwalls 1]
lassign [dict get $made walls] left right bottom top
set cx [expr {$L / 2}]
set cy [expr {$L / 2}]
set hole {}
foreach id [element list -tag sample] p [element array position -tag sample] {
    if {hypot([lindex $p 0] - $cx, [lindex $p 1] - $cy) < $a} {lappend hole $id}
}
element remove {*}$hole
set drilled [dict get [bond count] bonds]

# Returns each element's number of broken bonds, in element order (for snapshot -values).
proc brokenPerElement {} {
    set ids [element list]
    set count [dict create]
    foreach b [bond breaks] {
        dict incr count [dict get $b a]
        dict incr count [dict get $b b]
    }
    lmap id $ids {expr {[dict exists $count $id] ? [dict get $count $id] : 0}}
}
# Writes frame k of the block into the frames folder, if any. Returns nothing.
proc frame {k title} {
    global opt
    if {$opt(-frames) eq {}} return
    file mkdir $opt(-frames)
    snapshot write [file join $opt(-frames) [format frame_%03d.png $k]] -color value \
        -values [brokenPerElement] -unit "broken bonds" -range {0 3} -colormap viridis \
        -title $title -size 700x600
}
frame 0 "drilled: S1 = S3 = 0"

# The servo walls: each holds its face's stress over the block's side (per unit thickness).
# The gain is a fortieth of the stability bound 2 / (K dt), K the stiffness the wall meets
# first: its contacts with the L / (2 r) discs along it, each kn = E* R = 4 E_c per unit
# thickness (a wall's R* is the disc's radius). The contacts' dampers bound it too (the force
# read answers the wall's own speed through them: gain x damping < 1), which a tenth of the
# bound exceeded: the walls then swung between the speed limits, pumping energy in. The speed
# limit loads the block at a strain rate of at most 10/s (one wall moving), as ucs.tcl's short
# form.
set along [expr {$L / ($rock::rmin + $rock::rmax)}]
set gain [expr {0.05 / ($along * 4 * $rock::modulus * [sim timestep])}]
set speed [expr {10.0 * $L}]
# One wall of each pair under servo, the other fixed: with both, the pair has a neutral mode
# (the block sliding between them, the other pair's friction making their readings differ),
# which the servos drive at their speed limit.
foreach {w s} [list $right $S1 $top $S3] {
    wall servo $w -stress $s -area $L -gain $gain -maxspeed $speed
}
set chunks 16
set chunk 3000
for {set k 1} {$k <= $chunks} {incr k} {
    sim run -steps $chunk -quiet -progress 0
    if {$k % 4 == 0 || $k == $chunks} {frame [expr {($k + 3) / 4}] [format "S1 %.0f MPa (x), S3 %.0f MPa (y): %d broken bonds" \
        [expr {$S1 / 1e6}] [expr {$S3 / 1e6}] [dict get [bond count] broken]]}
}
# The stresses the servo walls hold (the fixed walls read less: the other pair's friction
# carries part of the load).
set sx [expr {[lindex [wall get $right -force] 0] / $L}]
set sy [expr {[lindex [wall get $top -force] 1] / $L}]

# The histogram of the broken bonds' angles near the hole, folded into [0, 90) degrees from x.
set bins [lrepeat 9 0]
set near 0
set alongY 0
foreach b [bond breaks] {
    lassign [dict get $b point] x y
    set dx [expr {$x - $cx}]
    set dy [expr {$y - $cy}]
    if {hypot($dx, $dy) > 2.5 * $a} continue
    set angle [expr {atan2(abs($dy), abs($dx)) * 180 / acos(-1)}]
    set i [expr {min(8, int($angle / 10))}]
    lset bins $i [expr {[lindex $bins $i] + 1}]
    incr near
    if {$angle > 60} {incr alongY}
}
set fh [open $opt(-csv) w]
puts $fh "angle_from_x_deg,broken_bonds"
foreach count $bins k {0 1 2 3 4 5 6 7 8} {puts $fh "[expr {10 * $k + 5}],$count"}
close $fh
set share [expr {$near ? double($alongY) / $near : 0}]
set c [bond count]
puts [format "borehole: %d discs, %d bonds after drilling a hole of radius %.3g mm; servo walls hold %.3g MPa (x) and %.3g MPa (y); %d bonds broken (%d tension, %d shear), %d within 2.5 radii of the hole, %.0f %% of those within 30 degrees of the y axis (uniform: 33 %%); histogram (10-degree bins from x) %s in %s" \
    [element count] $drilled [expr {$a * 1e3}] [expr {$sx / 1e6}] [expr {$sy / 1e6}] \
    [dict get $c broken] [dict get $c tension] [dict get $c shear] $near [expr {100 * $share}] \
    $bins $opt(-csv)]
dict create elements [element count] bonds $drilled sx $sx sy $sy broken [dict get $c broken] \
    near $near share $share bins $bins
