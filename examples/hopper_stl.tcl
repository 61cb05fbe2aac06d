# A conical hopper read from an STL file, discharging ellipsoids: the hopper is a triangle mesh
# (written here as an ASCII STL, as a CAD program would give it), an inlet pours turned
# ellipsoids into it until a target mass is in, a sink below the outlet takes those that have
# left, and the discharged mass against time is a time series whose steady slope is the mass
# flow rate. Frames of the discharge are written when a folder is given.
#
#   build/demlab examples/hopper_stl.tcl ?-short? ?-csv file? ?-frames folder?
#
# -short: three hundredths of a second of filling (the test suite's form). -csv: where the
# series goes (default hopper_stl.csv). -frames: PNG frames every 0.1 s into that folder.

set short 0
set csv hopper_stl.csv
set frames ""
for {set i 0} {$i < [llength $argv]} {incr i} {
    switch -- [lindex $argv $i] {
        -short {set short 1}
        -csv {set csv [lindex $argv [incr i]]}
        -frames {set frames [lindex $argv [incr i]]}
    }
}

set R 0.05         ;# radius of the hopper's top, m
set r0 0.009       ;# radius of its outlet, m
set H 0.06         ;# height of the cone, m

# Writes the cone as an ASCII STL of n sectors, two triangles each.
proc writeCone {path n top bottom h} {
    set f [open $path w]
    puts $f "solid hopper"
    set pi [expr {acos(-1)}]
    for {set k 0} {$k < $n} {incr k} {
        set a0 [expr {2 * $pi * $k / $n}]
        set a1 [expr {2 * $pi * ($k + 1) / $n}]
        set p1 [list [expr {$bottom * cos($a0)}] [expr {$bottom * sin($a0)}] 0]
        set p2 [list [expr {$bottom * cos($a1)}] [expr {$bottom * sin($a1)}] 0]
        set p3 [list [expr {$top * cos($a1)}] [expr {$top * sin($a1)}] $h]
        set p4 [list [expr {$top * cos($a0)}] [expr {$top * sin($a0)}] $h]
        foreach tri [list [list $p1 $p2 $p3] [list $p1 $p3 $p4]] {
            puts $f "  facet normal 0 0 0\n    outer loop"
            foreach p $tri { puts $f "      vertex $p" }
            puts $f "    endloop\n  endfacet"
        }
    }
    puts $f "endsolid hopper"
    close $f
}
set stl [file join [file dirname [file normalize $csv]] hopper_stl.stl]
writeCone $stl 48 $R $r0 $H

sim new
material add glass -density 2500 -young 5e6 -poisson 0.3 -restitution 0.5 -friction 0.5 \
    -rolling 0.02
behavior add gravity
sim timestep auto
set hopper [wall add mesh -file $stl -name hopper]

# The feed: ellipsoids of half axes 1.6 : 1.2 : 1 mm (scaled to bounding radii of 1.4-1.8 mm),
# turned at random, poured from above the cone until 30 g are in; the sink 3 cm below the
# outlet.
set massIn [expr {$short ? 0.002 : 0.03}]
inlet add feed -region [list cylinder [list 0 0 [expr {$H + 0.02}]] {0 0 1} [expr {0.7 * $R}] 0.01] \
    -radius {uniform 0.0014 0.0018} -shape superquadric -params {1.6 1.2 1 2 2} \
    -orientation random -massrate 0.4 -mass $massIn -velocity {0 0 -0.3} -seed 1
sink add out -point {0 0 -0.03} -normal {0 0 1}
set flow [series every -time 0.01 -file $csv \
    -quantities {time sink:out:mass sink:out:count inlet:feed:mass elements}]

if {$frames ne ""} {
    file mkdir $frames
    foreach f [glob -nocomplain -directory $frames hopper_*.png] {file delete $f}
    snapshot every -time 0.1 -dir $frames -format png -size 480x360 -color speed \
        -range {0 0.5} -position {0.16 -0.2 0.14} -lookat {0 0 0.02} -fov 35 \
        -title "ellipsoids through an STL hopper"
}
set tEnd [expr {$short ? 0.03 : 0.5}]
# A run of -time fixes its step count at its start; the automatic step shrinks as the inlet
# adds elements, so the run is repeated until the time is reached.
while {[sim time] < $tEnd - 1e-9} {
    sim run -time [expr {$tEnd - [sim time]}] -quiet -progress 0
}
if {$frames ne ""} {
    snapshot off
    foreach f [glob -directory $frames frame_*.png] {
        file rename -force $f [file join $frames [string map {frame_ hopper_} [file tail $f]]]
    }
}
series off $flow

# The flow rate: the slope of the discharged mass over the second half of the run.
set f [open $csv]
set rows [lrange [split [string trim [read $f]] \n] 1 end]
close $f
set half [lrange $rows [expr {[llength $rows] / 2}] end]
lassign [split [lindex $half 0] ,] t0 m0
lassign [split [lindex $half end] ,] t1 m1
set rate [expr {$t1 > $t0 ? ($m1 - $m0) / ($t1 - $t0) : 0}]
puts [format "%d elements in the hopper, %.1f g out, %.2f g/s over the last %.2f s" \
    [element count] [expr {1000 * $m1}] [expr {1000 * $rate}] [expr {$t1 - $t0}]]
list [element count] $m1 $rate
