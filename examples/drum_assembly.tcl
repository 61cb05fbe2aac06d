# Figure 1-9 of the thesis: a drum built as a rigid assembly of quadrilaterals, turning, with
# particles of mixed shapes and sizes inside (discs, squares, triangles and superellipses), in
# 2D. The drum is one element: an assembly (`element assembly`) of quadrilaterals round a ring,
# with -lifters n bars (rectangles standing on the ring's inner faces, evenly spaced so the
# drum's centre of mass stays on its axis), fixed and given an angular velocity, so it turns at
# that speed whatever the grains push. Every grain meets the quadrilaterals through the polygon's
# own rows.
#
#   build/demlab examples/drum_assembly.tcl ?-short? ?-lifters n? ?-turns t? ?-csv file? ?-frames dir?
#
# Writes a row every 0.05 s (time, the drum's angle, the bed's centre of mass, its kinetic
# energy) and returns a dict: grains, turns, angle, bed_x, bed_y, inside, steps, us_per_step.
array set opt {-short 0 -lifters 0 -turns 1 -csv drum_assembly.csv -frames {}}
for {set i 0} {$i < [llength $argv]} {incr i} {
    set a [lindex $argv $i]
    switch -- $a {
        -short {set opt(-short) 1}
        -lifters - -turns - -csv - -frames {
            if {$i + 1 >= [llength $argv]} {
                error "drum_assembly.tcl: $a needs a value" {} {DEMLAB ARGS}
            }
            set opt($a) [lindex $argv [incr i]]
        }
        default {error "drum_assembly.tcl: unknown option \"$a\"" {} {DEMLAB OPTION}}
    }
}
if {![string is integer -strict $opt(-lifters)] || $opt(-lifters) < 0 || $opt(-lifters) == 1 ||
        $opt(-lifters) > 20} {
    error "drum_assembly.tcl: bad lifters \"$opt(-lifters)\": must be 0 or 2 to 20" {} {DEMLAB VALUE LIFTERS}
}
if {![string is double -strict $opt(-turns)] || !($opt(-turns) > 0)} {
    error "drum_assembly.tcl: bad turns \"$opt(-turns)\": must be a positive number" {} {DEMLAB VALUE TURNS}
}

set R 0.05          ;# the drum's inner radius, m
set shell 0.004     ;# its wall's thickness
set segments 40     ;# quadrilaterals round the ring
set omega 1.5       ;# rad/s, counterclockwise (Froude number omega^2 R / g = 0.011: rolling)
set pi [expr {acos(-1)}]
sim new -dim 2
material add glass -density 2500 -young 1e7 -poisson 0.3 -restitution 0.3 -friction 0.5
material add steel -density 7800 -young 1e7 -poisson 0.3 -restitution 0.3 -friction 0.5

# The grains first: a packing keeps new grains clear of every element's bounding circle, and the
# drum's holds them all. A box clear of the ring and the lifters (the short form: its lower
# part).
set region [expr {$opt(-short) ? {box {-0.032 -0.033} {0.032 0.008}} : {box {-0.033 -0.033} {0.033 0.033}}}]
set counts [expr {$opt(-short) ? {12 12 8 8} : {45 35 25 25}}]
lassign $counts nd ns nt ne
set radii {uniform 0.0015 0.0025}
pack random -region $region -radius $radii -count $nd -seed 1 -material glass -tags {disc grain}
pack random -region $region -radius $radii -count $ns -seed 2 -material glass -tags {square grain} \
    -shape polygon -params {-1 -1 1 -1 1 1 -1 1} -orientation random
pack random -region $region -radius $radii -count $nt -seed 3 -material glass -tags {triangle grain} \
    -shape polygon -params {0 1 -0.866 -0.5 0.866 -0.5} -orientation random
pack random -region $region -radius $radii -count $ne -seed 4 -material glass -tags {superellipse grain} \
    -shape superellipse -params {1 0.6 4} -orientation random
set grains [element count]

# The drum: quadrilaterals between radii R and R + shell, then the lifters: bars 8 mm tall and
# 4 mm wide whose outer side lies on a quadrilateral's inner face (its chord, at R cos(pi/n)).
set members {}
for {set k 0} {$k < $segments} {incr k} {
    set a0 [expr {2 * $pi * $k / $segments}]
    set a1 [expr {2 * $pi * ($k + 1) / $segments}]
    set corners {}
    foreach a [list $a0 $a1] r [list $R $R] {lappend corners [expr {$r * cos($a)}] [expr {$r * sin($a)}]}
    foreach a [list $a1 $a0] {
        lappend corners [expr {($R + $shell) * cos($a)}] [expr {($R + $shell) * sin($a)}]
    }
    lappend members [list polygon -params $corners]
}
set chord [expr {$R * cos($pi / $segments)}]
for {set k 0} {$k < $opt(-lifters)} {incr k} {
    # Centred on segment k * segments / lifters: its mid angle.
    set s [expr {$k * $segments / $opt(-lifters)}]
    set a [expr {2 * $pi * ($s + 0.5) / $segments}]
    set h 0.008
    set w 0.002
    lappend members [list polygon -params [list [expr {-$h / 2}] [expr {-$w}] [expr {$h / 2}] [expr {-$w}] \
        [expr {$h / 2}] $w [expr {-$h / 2}] $w] -position [list [expr {($chord - $h / 2) * cos($a)}] \
        [expr {($chord - $h / 2) * sin($a)}]] -orientation $a]
}
set drum [element add -shape assembly -params [element assembly -members $members] -material steel \
    -tags drum]
element set $drum -fixed 1 -angularvelocity $omega
behavior add gravity -g {0 -9.81}

# The bed's centre of mass and kinetic energy.
proc bed {} {
    set m 0.0; set mx 0.0; set my 0.0; set ke 0.0
    foreach id [element list -tag grain] {
        set mi [element get $id -mass]
        lassign [element get $id -position] x y
        lassign [element get $id -velocity] vx vy
        set m [expr {$m + $mi}]
        set mx [expr {$mx + $mi * $x}]
        set my [expr {$my + $mi * $y}]
        set ke [expr {$ke + 0.5 * $mi * ($vx * $vx + $vy * $vy)}]
    }
    list [expr {$mx / $m}] [expr {$my / $m}] $ke
}
# The count of grains inside the drum's inner circle.
proc inside {} {
    set n 0
    foreach id [element list -tag grain] {
        lassign [element get $id -position] x y
        if {hypot($x, $y) < $::R} {incr n}
    }
    return $n
}

if {$opt(-frames) ne ""} {
    file mkdir $opt(-frames)
    snapshot every -time 0.25 -dir $opt(-frames) -size 640x640 -color tag \
        -tags {drum disc square triangle superellipse} -timestamp 1 -legend 0
}
set duration [expr {$opt(-short) ? 0.1 : $opt(-turns) * 2 * $pi / $omega}]
set out [open $opt(-csv) w]
puts $out "time,drum_angle,bed_x,bed_y,bed_kinetic_J_per_m"
set steps0 [dict get [sim info] steps]
set c0 [clock microseconds]
set chunk [expr {$opt(-short) ? 0.02 : 0.05}]
while {[sim time] < $duration - 1e-9} {
    sim run -time $chunk -quiet -progress 0
    lassign [bed] bx by ke
    puts $out [format "%.4f,%.6f,%.6f,%.6f,%.4g" [sim time] [lindex [element get $drum -orientation] 0] $bx $by $ke]
}
set elapsed [expr {[clock microseconds] - $c0}]
close $out
if {$opt(-frames) ne ""} {snapshot off}
set steps [expr {[dict get [sim info] steps] - $steps0}]
lassign [bed] bx by ke
set r [dict create grains $grains turns [expr {[sim time] * $omega / (2 * $pi)}] \
    angle [lindex [element get $drum -orientation] 0] bed_x $bx bed_y $by inside [inside] \
    steps $steps us_per_step [expr {double($elapsed) / $steps}]]
puts [format "drum of quadrilaterals (%d lifters): %d grains, %.2f turns, bed centre (%.4f, %.4f) m, %d inside, %.1f us a step" \
    $opt(-lifters) $grains [dict get $r turns] $bx $by [inside] [dict get $r us_per_step]]
return $r
