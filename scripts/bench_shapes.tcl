# The cost of a superquadric bed against a bed of spheres of the same bounding radius: run by
# scripts/bench-shapes (which see). Arguments: variant count settle-steps timed-steps.
# Prints one CSV row: variant,n,steps,seconds,cpu_seconds,us_per_step,contacts,ns_per_contact
lassign $argv variant count settle timed
array set shapes {
    sphere {}
    ellipsoid {2 1.5 1 2 2}
    blocky {2 1.5 1 4 4}
    blocky-4-3 {2 1.5 1 4 3}
    blocky-10 {2 1.5 1 10 10}
    clump {0 0 0 1 1.2 0 0 0.8 0 1.2 0 0.8 0 0 1.2 0.8}
    polyhedron {-2 -1.5 -1 2 -1.5 -1 -2 1.5 -1 2 1.5 -1 -2 -1.5 1 2 -1.5 1 -2 1.5 1 2 1.5 1}
    sphere-meshfloor {}
    levelset {}
}
if {![info exists shapes($variant)]} {
    puts stderr "bench_shapes: unknown variant \"$variant\": [array names shapes]"
    exit 2
}
source [file join [file dirname [info script]] bench_common.tcl]
benchScene
set side 0.06
if {$variant eq "sphere-meshfloor"} {
    # The floor as a mesh of 200 triangles (10 x 10 squares) instead of a plane.
    set stl [file join [file dirname [info script]] .. build bench-floor.stl]
    set f [open $stl w]
    puts $f "solid floor"
    set m 10
    for {set i 0} {$i < $m} {incr i} {
        for {set j 0} {$j < $m} {incr j} {
            set x0 [expr {$side * $i / $m}]; set x1 [expr {$side * ($i + 1) / $m}]
            set y0 [expr {$side * $j / $m}]; set y1 [expr {$side * ($j + 1) / $m}]
            foreach tri [list [list $x0 $y0 $x1 $y0 $x1 $y1] [list $x0 $y0 $x1 $y1 $x0 $y1]] {
                lassign $tri a b c d e g
                puts $f "facet normal 0 0 1\nouter loop\nvertex $a $b 0\nvertex $c $d 0\nvertex $e $g 0\nendloop\nendfacet"
            }
        }
    }
    puts $f "endsolid floor"
    close $f
    wall add mesh -file $stl
} else {
    wall add plane -point {0 0 0} -normal {0 0 1}
}
addSideWalls $side
# Bounding balls at a solid fraction of about 0.2 (a loose start that settles in 0.1 s).
set region [list box {0 0 0} [list $side $side [expr {$count * 5e-5}]]]
if {$variant eq "levelset"} {
    # The ellipsoid (2 : 1.5 : 1) as a level set: its function sampled at a spacing of 1/4 of the
    # short half axis and re-distanced (about 600 surface nodes).
    set shapes(levelset) [demlab::levelset {x y z} {sqrt(($x / 2) ** 2 + ($y / 1.5) ** 2 + $z ** 2) - 1} \
        -box {{-2.5 -2 -1.5} {2.5 2 1.5}} -spacing 0.25]
}
if {$shapes($variant) eq {}} {
    pack random -region $region -radius 0.002 -count $count -seed 1
} else {
    pack random -region $region -radius 0.002 -count $count -seed 1 \
        -shape [expr {$variant in {clump polyhedron levelset} ? $variant : "superquadric"}] -params $shapes($variant) \
        -orientation random
}
sim timestep 1e-5
sim run -steps $settle -quiet
set c0 [cpuSeconds]
set t0 [clock microseconds]
sim run -steps $timed -quiet
set seconds [expr {([clock microseconds] - $t0) * 1e-6}]
set cpu [expr {[cpuSeconds] - $c0}]
set contacts [llength [query contacts]]
puts [format "%s,%d,%d,%.3f,%.2f,%.1f,%d,%.0f" $variant $count $timed $seconds $cpu \
    [expr {$cpu / $timed * 1e6}] $contacts [expr {$contacts > 0 ? $cpu / $timed / $contacts * 1e9 : 0}]]
