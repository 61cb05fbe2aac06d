# Figure 3-9 of the thesis: a sample of grains of mixed shapes (discs, squares, triangles) compacted
# between two long plates, in 2D. The plates are what the thesis's "uninformed user" writes:
# rectangles (polygon elements) as long as the box, 60 times a grain's size, the outliers that
# defeat a grid whose cell follows the largest object. CGrid files them by size, so the neighbour
# search is not the cost; the cost is the narrow phase: candidates come from bounding circles, and
# a plate's circle holds every grain, so each grain is tested against both plates every step.
# -plates walls gives the expert's answer (finite walls moving at the same speed), for comparison.
#
#   build/demlab examples/compaction.tcl ?-short? ?-plates elements|walls? ?-csv file? ?-frames dir?
#
# The lower plate is fixed, the upper one moves down at 0.1 m/s (quasi-static: the grains' own
# collision time is 40 times shorter than the time to cross a grain); side walls hold the sample.
# Writes a row every 0.02 s (gap, solid fraction, force on the upper plate per unit thickness)
# until the solid fraction between the plates reaches 0.75, and returns a dict: grains,
# fraction0, fraction, force, steps, us_per_step.
array set opt {-short 0 -plates elements -csv compaction.csv -frames {}}
for {set i 0} {$i < [llength $argv]} {incr i} {
    set a [lindex $argv $i]
    switch -- $a {
        -short {set opt(-short) 1}
        -plates - -csv - -frames {
            if {$i + 1 >= [llength $argv]} {
                error "compaction.tcl: $a needs a value" {} {DEMLAB ARGS}
            }
            set opt($a) [lindex $argv [incr i]]
        }
        default {error "compaction.tcl: unknown option \"$a\"" {} {DEMLAB OPTION}}
    }
}
if {$opt(-plates) ni {elements walls}} {
    error "compaction.tcl: bad plates \"$opt(-plates)\": must be elements or walls" {} {DEMLAB VALUE PLATES}
}

set W 0.1                                   ;# the box's width, m
set H [expr {$opt(-short) ? 0.06 : 0.12}]   ;# the loose sample's height
set v 0.1                                   ;# the upper plate's speed, m/s
set target 0.75                             ;# the solid fraction at which the test ends
set counts [expr {$opt(-short) ? {25 25 20} : {50 50 40}}]
sim new -dim 2
material add grain -density 2500 -young 1e7 -poisson 0.3 -restitution 0.3 -friction 0.4
# Grains first: a packing keeps new grains clear of every element's bounding circle, and a
# plate's would cover the box.
set region [list box {0 0} [list $W $H]]
set radii {uniform 0.002 0.003}
lassign $counts nd ns nt
pack random -region $region -radius $radii -count $nd -seed 1
pack random -region $region -radius $radii -count $ns -seed 2 -shape polygon \
    -params {-1 -1 1 -1 1 1 -1 1} -orientation random
pack random -region $region -radius $radii -count $nt -seed 3 -shape polygon \
    -params {0 1 -0.866 -0.5 0.866 -0.5} -orientation random
set grains [element count]
wall add plane -point {0 0} -normal {1 0}
wall add plane -point [list $W 0] -normal {-1 0}
set t 0.002                                 ;# the plates' half thickness
set L [expr {1.5 * $W}]                      ;# their half length
if {$opt(-plates) eq "elements"} {
    set plate [list [expr {-$L}] [expr {-$t}] $L [expr {-$t}] $L $t [expr {-$L}] $t]
    set bottom [element add -shape polygon -params $plate -position [list [expr {$W / 2}] [expr {-$t}]]]
    set top [element add -shape polygon -params $plate -position [list [expr {$W / 2}] [expr {$H + $t}]]]
    element set $bottom -fixed 1
    element set $top -fixed 1 -velocity [list 0 [expr {-$v}]]
    proc plateY {} {expr {[lindex [element get $::top -position] 1] - $::t}}
    # The force the grains put on the upper plate (up, per unit thickness): its contacts' forces.
    proc plateForce {} {
        set f 0.0
        foreach c [query contacts -element $::top] {
            if {[dict get $c wall] ne ""} continue  ;# the side walls hold the plate's ends
            set fy [lindex [dict get $c force] 1]
            set f [expr {$f + ([dict get $c b] eq $::top ? $fy : -$fy)}]
        }
        return $f
    }
} else {
    wall add plane -name bottom -point {0 0} -normal {0 1}
    wall add finite -name top -point [list [expr {$W / 2}] $H] -normal {0 -1} -halfextents $L \
        -velocity [list 0 [expr {-$v}]]
    proc plateY {} {lindex [wall get top -point] 1}
    proc plateForce {} {lindex [wall get top -force] 1}
}
# Every grain's area, for the solid fraction between the plates.
set area 0.0
foreach id [element list] {
    if {$opt(-plates) eq "elements" && $id in [list $bottom $top]} continue
    set area [expr {$area + [element get $id -mass] / 2500.0}]
}
set fraction0 [expr {$area / ($W * $H)}]
if {$opt(-frames) ne ""} {
    file mkdir $opt(-frames)
    snapshot every -time [expr {(1 - $fraction0 / $target) * $H / $v / 5}] -dir $opt(-frames) \
        -size 640x480 -color id -timestamp 1 -legend 0
}
set out [open $opt(-csv) w]
puts $out "time,gap,solid_fraction,force_N_per_m"
set steps0 [dict get [sim info] steps]
set c0 [clock microseconds]
set fraction $fraction0
while {$fraction < $target && [plateY] > 0.2 * $H} {
    sim run -time 0.02 -quiet -progress 0
    set gap [plateY]
    set fraction [expr {$area / ($W * $gap)}]
    set force [plateForce]
    puts $out [format "%.6f,%.7f,%.4f,%.4g" [sim time] $gap $fraction $force]
}
set elapsed [expr {[clock microseconds] - $c0}]
close $out
if {$opt(-frames) ne ""} {snapshot off}
set steps [expr {[dict get [sim info] steps] - $steps0}]
set r [dict create grains $grains fraction0 $fraction0 fraction $fraction force $force steps $steps \
    us_per_step [expr {double($elapsed) / $steps}]]
puts [format "compaction (%s): %d grains, solid fraction %.3f -> %.3f, plate force %.4g N/m, %.1f us a step" \
    $opt(-plates) $grains $fraction0 $fraction $force [dict get $r us_per_step]]
return $r
