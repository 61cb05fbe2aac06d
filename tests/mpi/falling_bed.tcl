# A bed of balls falling into a box, the script a user runs alone or as `mpirun -np N demlab
# falling_bed.tcl`: every rank runs it, the first run spreads the scene over the ranks. It
# prints (rank 0 alone under mpirun) what script_ranks.sh compares between the two runs, and
# checks on its own what only a distributed run does: which commands are refused, and that an
# error raised on every rank is caught alike on every rank.
proc check {what ok} {
    if {!$ok} { error "falling_bed.tcl: $what" {} {TEST FAILED} }
}
proc vdot {a b} {
    set s 0.0
    foreach x $a y $b { set s [expr {$s + $x * $y}] }
    return $s
}
proc expectError {code script} {
    set failed [catch {uplevel 1 $script} msg opts]
    check "\"$script\" should fail with $code, gave: $msg" \
        [expr {$failed && [string match $code* [dict get $opts -errorcode]]}]
}

source [file join [file dirname [info script]] bed_scene.tcl]
lassign [makeBed] gone ids
check "the first new element reuses the removed one's slot" [expr {[lindex $ids 0] == $gone + 2**32}]
# A VTK series: frame 0 now (every rank holds the whole scene), then pieces a rank.
if {$argc > 0} {
    dump every -steps 2000 -dir [file join [lindex $argv 0] series] -parts {elements walls}
    snapshot every -steps 2000 -dir [file join [lindex $argv 0] frames] -size 320x240
}
# A time series recorded through the runs: every rank records the whole scene's rows (counts,
# energies and wall forces summed over the ranks, the script's query collective), rank 0 writes
# the file.
set seriesFile [expr {$argc > 0 ? [list -file [file join [lindex $argv 0] series.csv]] : {}}]
set seriesOf {time step elements contacts kinetic elastic damping wall:0:fz wall:0:work}
set ser [series every -steps 500 -quantities [list {*}$seriesOf {ztop {lindex [query bounds] 1 2} m}] \
    {*}$seriesFile]
# A load and a torque ramp on one grain each: the rank owning the grain, wherever it goes,
# applies them (found by the id the script holds).
behavior add load -element [lindex $ids 42] -force {2e-4 0 0}
behavior add torque-ramp -element [lindex $ids 43] -torque {0 1e-8 0} -rate {0 1e-6 0}
# Blocked degrees of freedom: a grain fixed where it starts (an obstacle the bed falls on, its
# contacts on whichever ranks hold its copies), one that cannot move vertically.
element set [lindex $ids 44] -fixed 1
element set [lindex $ids 45] -block z
# Tags, under the ids the script holds, alike on every rank: every seventh grain tagged in
# reverse order (a tag lists its members in the order they were tagged, not by id), and ten
# grains pushed by a load on their tag (each rank pushes the members it owns).
set seventh {}
for {set k 0} {$k < 1200} {incr k 7} { lappend seventh [lindex $ids $k] }
element tag seventh {*}[lreverse $seventh]
element tag pushed {*}[lrange $ids 50 59]
behavior add load -tag pushed -force {0 1e-4 0}
set fixedAt [element get [lindex $ids 44] -position]
set heldVz [lindex [element get [lindex $ids 45] -velocity] 2]
set ranks [sim ranks]
check "no rank before the run should be distributed" [expr {![dict get $ranks distributed]}]

set report [sim run -steps 4000 -quiet]
# (Spun by its ramp to ~90 rad/s among its neighbours, the grain's spin then grows the ranks'
# round-off faster than the bed does: compared here, 4000 steps in.)
puts "spin_ramped [element get [lindex $ids 43] -angularvelocity]"
set ranks [sim ranks]
set n [dict get $ranks ranks]
check "the scene is distributed when mpirun started more than one rank" \
    [expr {[dict get $ranks distributed] == ($n > 1)}]

# What the comparison reads: one key and its value a line.
puts "steps [dict get $report steps]"
puts "time [sim time]"
puts "rebuilds [dict get $report rebuilds]"
set counts [query counts]
puts "elements [dict get $counts elements]"
puts "walls [dict get $counts walls]"
puts "contacts [dict get $counts contacts]"
puts "count [element count]"
puts "bounds [join [query bounds]]"
set e [query energy]
foreach k {kinetic gravitational elastic damping friction wallwork} { puts "$k [dict get $e $k]" }
# The micromechanics of a region in the bed: the whole scene's sample on every rank.
set region {box {0.006 0.006 0.004} {0.034 0.034 0.02}}
puts "stress [dict get [query stress -region $region] tensor]"
puts "stresstagged [dict get [query stress -tag seventh -region $region] tensor]"
set z [query coordination -region $region]
puts "coordination [dict get $z elements] [dict get $z contacts] [dict get $z n0] [dict get $z n1]"
puts "coordinationz [dict get $z z] [dict get $z mechanical]"
puts "fabric [dict get [query fabric -region $region] tensor]"
set p [query packing -region $region]
puts "packing [dict get $p fraction] [dict get $p mass]"
set m [query motion -region $region]
puts "motion [dict get $m velocity] [dict get $m temperature]"
set cg [query cg -width 0.004 -spacing 0.004 -grid {box {0.004 0.004 0.004} {0.036 0.036 0.02}}]
puts "cgmass [dict get $cg mass]"
# The contacts, gathered: their number, one element's, the sum of the normal forces.
set all [query contacts]
set sum 0.0
foreach k $all { set sum [expr {$sum + abs([vdot [dict get $k force] [dict get $k normal]])}] }
puts "contactlist [llength $all] [query contacts -count] [llength [query contacts -element [lindex $ids 600]]]"
puts "contactforces $sum"
expectError {DEMLAB LOOKUP ELEMENT} "query contacts -element $gone"
puts "floorforce [wall get 0 -force]"
puts "sideforce [wall get 1 -force]"
foreach k {0 1 17 600 1199} {
    set id [lindex $ids $k]
    puts "position$k [element get $id -position]"
    puts "velocity$k [element get $id -velocity]"
}
puts "tagcount [element count -tag seventh] [element count -tag pushed] [element count -tag none]"
puts "taglist [element list -tag seventh]"
puts "tagids [element array id -tag pushed]"
puts "position_tagged [concat {*}[element array position -tag pushed]]"
puts "tags [element get [lindex $ids 56] -tags] / [element get [lindex $ids 7] -tags]"
set id [lindex $ids 17]
check "element get returns the dict with the id the script knows" \
    [expr {[dict get [element get $id] id] == $id && [dict get [element get $id] radius] > 0}]
foreach q [list {*}$seriesOf ztop] {
    puts "series[string map {: _} $q] [series get $ser -quantity $q]"
}
check "series list answers alike" [expr {[dict get [lindex [series list] 0] rows] == 9}]
if {$argc > 0} {
    set f [open [file join [lindex $argv 0] series.csv]]
    set lines [split [string trim [read $f]] \n]
    close $f
    puts "seriesfile [llength $lines] [lindex $lines 0] [lindex [split [lindex $lines end] ,] 1]"
    # A plot of the rows every rank holds, drawn once (rank 0): a PNG of the size asked for.
    set png [series plot $ser -file [file join [lindex $argv 0] series.png] -y {kinetic elastic} \
        -size {400 300} -logy]
    set f [open $png rb]
    binary scan [read $f 24] a8@16IuIu magic w h
    close $f
    puts "seriesplot [file tail $png] [expr {$magic eq "\x89PNG\r\n\x1a\n"}] $w $h"
}
puts "list [lsort -integer [element list]]"
check "element list has the pack's ids" [expr {[lsort -integer [element list]] eq [lsort -integer $ids]}]
# element array: by id once distributed, in the scene's order alone: sorted here by id.
set rows {}
foreach i [element array id] x [element array position] r [element array radius] {
    lappend rows [list $i {*}$x $r]
}
puts "positions [concat {*}[lmap row [lsort -integer -index 0 $rows] {lrange $row 1 3}]]"
puts "radii [lmap row [lsort -integer -index 0 $rows] {lindex $row 4}]"

# VTK files: alone one .vtp a part; on several ranks a piece a rank under a .pvtp (compared by
# script_ranks.sh with vtk_compare.py).
if {$argc > 0} {
    set files [dump vtk [file join [lindex $argv 0] bed]]
    set want [expr {$n > 1 ? {bed_elements.pvtp bed_walls.vtp bed_contacts.pvtp}
                           : {bed_elements.vtp bed_walls.vtp bed_contacts.vtp}}]
    check "dump vtk returns $want, gave $files" [expr {[lmap f $files {file tail $f}] eq $want}]
    snapshot write [file join [lindex $argv 0] bed.png] -size 320x240 -color speed
    snapshot write [file join [lindex $argv 0] tagged.png] -size 320x240 -tags {seventh pushed} \
        -color tag
    dump csv [file join [lindex $argv 0] bed.csv] -fields {id radius x y z vx vy vz}
    dump lammps [file join [lindex $argv 0] bed.data]
    if {$n > 1} {
        expectError {DEMLAB MPI UNSUPPORTED} {snapshot write /tmp/never.png -chains 1}
    }
}

# Errors raised on every rank alike, caught alike.
expectError {DEMLAB LOOKUP ELEMENT} {element get 5000}
expectError {DEMLAB LOOKUP ELEMENT} "element get $gone"
expectError {DEMLAB LOOKUP ELEMENT} "element set $gone -velocity {0 0 0}"
expectError {DEMLAB VALUE VELOCITY} "element set [lindex $ids 5] -velocity {1e9 0 0}"
check "a fixed grain should stay where it was" [expr {[element get [lindex $ids 44] -position] eq $fixedAt}]
check "a grain blocked along z should keep its vertical speed" \
    [expr {[lindex [element get [lindex $ids 45] -velocity] 2] == $heldVz}]
# Blocked after the first run (every rank lists it, its owner holds it); one freed.
element set [lindex $ids 5] -block {x y rz}
element set [lindex $ids 45] -block {}
puts "blocked [element get [lindex $ids 44] -blocked] [element get [lindex $ids 5] -blocked] [element get [lindex $ids 45] -blocked] [element get [lindex $ids 44] -fixed]"
expectError {DEMLAB LOOKUP ELEMENT} "element set $gone -fixed 1"
# Tags changed after the run, and two grains removed by their tag.
expectError {DEMLAB VALUE TAG} "element tag 12 [lindex $ids 3]"
expectError {DEMLAB LOOKUP ELEMENT} "element tag late $gone"
element untag seventh [lindex $ids 7]
element tag doomed [lindex $ids 21] [lindex $ids 28]
puts "removedtag [element remove -tag doomed] [element count] [element count -tag seventh] [element count -tag doomed]"
if {$n > 1} {
    set before [element count]
    expectError {DEMLAB VALUE} {element add -radius -1 -position {0.02 0.02 0.1}}
    check "a refused element add changes nothing" [expr {[element count] == $before}]
    # Rank 0 writes the gathered checkpoint; its failure is every rank's.
    expectError {DEMLAB IO OPEN} {sim save /nonexistent-dir/bed.dcp}
    # So does a series file's.
    expectError {DEMLAB IO OPEN} {series every -steps 10 -quantities step -file /nonexistent-dir/s.csv}
    # And a plot's.
    expectError {DEMLAB IO GNUPLOT} "series plot $ser -file /nonexistent-dir/p.png -y kinetic"
}
# A kept copy of a distributed scene (each rank its part) goes on as the scene does, bit for bit.
sim keep settled
set before [sim run -steps 100 -quiet]
set once [element get [lindex $ids 600] -position]
sim restore settled
sim run -steps 100 -quiet
check "a restored copy goes on bit for bit" [expr {[element get [lindex $ids 600] -position] eq $once}]
sim restore settled
# Edits after a run, each by the rank owning the element: one grain thrown into the bed, one
# lifted above it, one spun; the ledger's reference moves with them on every rank.
element set [lindex $ids 600] -velocity {0.1 0 -0.5}
element set [lindex $ids 17] -position {0.02 0.02 0.045} -velocity {0 0 -1}
element set [lindex $ids 1199] -angularvelocity {0 5 0} -orientation {0 1 0 0}
puts "edited [element get [lindex $ids 17] -position] [element get [lindex $ids 600] -velocity]"
# A side wall set moving inwards: every rank holds every wall and sets it alike.
wall set 2 -velocity {-0.002 0 0}
# A lid added over a corner of the bed, just into its highest grains there (every rank adds it
# alike); its force and work are the sums of the ranks' contacts with it.
set top 0
foreach x [element array position] r [element array radius] {
    lassign $x px py pz
    if {$px < 0.016 && $py < 0.016} { set top [expr {max($top, $pz + $r)}] }
}
set lid [wall add finite -point [list 0.008 0.008 [expr {$top - 2e-5}]] -normal {0 0 1} \
    -axis {1 0 0} -halfextents {0.008 0.008} -material glass -name lid]
# It holds a force on the grains under it: the servo reads the whole force, summed over the
# ranks, the same on every rank.
wall servo $lid -force 0.01 -gain 0.5 -maxspeed 0.01
# The material and gravity changed: every rank's elements take the new density, and the ranks
# decide together again what the scene uses and its step.
material set glass -friction 0.3 -density 2600
behavior remove [dict get [lindex [behavior list] 0] id]
behavior add gravity -g {0.5 0 -9.81}
# A load on a tag and a torque ramp on one grain added after the run: each rank acts on the
# elements it owns; an unknown grain refused alike.
behavior add load -tag seventh -force {0 -2e-5 0}
behavior add torque-ramp -element [lindex $ids 600] -torque {1e-9 0 0} -rate {0 0 1e-7}
expectError {DEMLAB LOOKUP ELEMENT} "behavior add load -element $gone -force {0 0 1e-4}"
expectError {DEMLAB LOOKUP ELEMENT} "behavior add torque-ramp -element $gone -torque {0 0 1e-9} -rate {0 0 0}"
# A grain added on the ranks: the id the serial scene gives, the grain at once where queries
# look (the rank whose box holds it takes it), falling into the bed.
set under 0
foreach x [element array position] r [element array radius] {
    lassign $x px py pz
    if {hypot($px - 0.03, $py - 0.012) < 0.004} { set under [expr {max($under, $pz + $r)}] }
}
set added [element add -radius 0.002 -position [list 0.03 0.012 [expr {$under + 0.0025}]] \
    -velocity {0 0 -0.5} -name dropped -tags {top seventh}]
puts "addedid $added [element count] [llength [element list]]"
puts "addedname [dict get [element get dropped] id] [element get $added -name] [element get dropped -tags] [element count -tag top] [lindex [element list -tag seventh] end]"
expectError {DEMLAB EXISTS NAME} {element add -radius 0.001 -position {0.02 0.02 0.1} -name dropped}
puts "addedstate [element get $added -position] [element get $added -velocity]"
# A series added on the ranks (collective: its first row is the whole scene's now).
set ser2 [series every -steps 100 -quantities {step contacts wall:2:fx}]
# The run goes on after them, together.
set report [sim run -steps 500 -quiet]
foreach q {step contacts wall:2:fx} { puts "series2[string map {: _} $q] [series get $ser2 -quantity $q]" }
puts "position_added [element get $added -position]"
puts "velocity_added [element get $added -velocity]"
puts "addedcontacts [llength [query contacts -element $added]]"
puts "residual2 [dict get $report residual]"
puts "movedwall [wall get 2 -force] [wall get 2 -work]"
puts "lidforce [wall get $lid -force] [wall get $lid -work]"
puts "lidpoint [wall get $lid -point]"
foreach k {17 600 1199} {
    puts "position_after$k [element get [lindex $ids $k] -position]"
    puts "velocity_after$k [element get [lindex $ids $k] -velocity]"
}
# Grains removed on the ranks (collective, all or none): five across the bed (some held by other
# ranks as ghosts, whose copies go at the next step's search), the grain added above, and one
# named twice. A second remove naming an unknown id removes nothing.
set gone2 [lmap k {100 350 640 880 1010} {lindex $ids $k}]
set before [element count]
expectError {DEMLAB LOOKUP ELEMENT} "element remove [lindex $gone2 0] 999999"
check "a refused element remove changes nothing" [expr {[element count] == $before}]
set removed [element remove {*}$gone2 $added [lindex $gone2 0]]
puts "removed $removed [element count] [llength [element list]] [dict get [query counts] contacts]"
expectError {DEMLAB LOOKUP ELEMENT} "element get [lindex $gone2 1]"
expectError {DEMLAB LOOKUP} {element get dropped}
puts "removednamed [element count -tag top] [element count -tag seventh]"
# A side wall removed alike on every rank (the lid, the last wall, takes its place among them).
wall remove 1
puts "wallsleft [llength [wall list]] [dict get [wall get $lid] id]"
set report [sim run -steps 100 -quiet]
puts "residual3 [dict get $report residual]"
puts "contacts3 [dict get [query counts] contacts]"
foreach k {17 600 1199} {
    puts "position_removed$k [element get [lindex $ids $k] -position]"
    puts "velocity_removed$k [element get [lindex $ids $k] -velocity]"
}
puts "position_loaded [element get [lindex $ids 42] -position]"
# An element added after them takes the handle the serial scene gives (the last slot freed).
set again [element add -radius 0.002 -position {0.02 0.02 0.045} -velocity {0 0 -0.5}]
puts "againid $again [element count]"
sim run -steps 100 -quiet
puts "position_again [element get $again -position]"
# The automatic step is the whole scene's on every rank: a run of -time counts the same steps.
sim timestep auto
puts "autostep [sim timestep]"
puts "timesteps [dict get [sim run -time 0.002 -quiet] steps]"
puts "position3 [element get [lindex $ids 600] -position]"
puts "contacts2 [dict get [query counts] contacts]"
puts "position2 [element get [lindex $ids 600] -position]"
