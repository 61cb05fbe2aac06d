# A dense sheared periodic cell (scripts/bench-periodic): N frictional spheres at solid fraction
# 0.58 grown in a Lees-Edwards cell, then 1000 timed steps. Prints one CSV row: n, kernel (the
# DEMLAB_KERNEL in force), contacts, microseconds per step, the contact pass's and the search's
# microseconds per step, neighbour searches.
#   build/demlab scripts/bench_periodic.tcl N
set n [lindex $argv 0]
set d 0.002; set phi 0.58
set L [expr {($n * acos(-1) / 6 * $d ** 3 * 1.04 / $phi) ** (1.0 / 3)}]
sim new
material add glass -density 2500 -young 1e8 -poisson 0.25 -restitution 0.6 -friction 0.5
set s [expr {(1.0 / 3) ** (1.0 / 3)}]
pack random -region [list box {0 0 0} [list $L $L $L]] -count $n -seed 1 \
    -radius [list uniform [expr {0.4 * $d * $s}] [expr {0.6 * $d * $s}]]
periodic set -axes {x y z} -lo {0 0 0} -hi [list $L $L $L] -shear 10
foreach e [element list] {
    set y [lindex [element get $e -position] 1]
    element set $e -velocity [list [expr {10 * ($y - $L / 2)}] 0 0]
}
set grow [expr {int(ceil(log(1.0 / $s) / log(1.01)))}]
set f [expr {(1.0 / $s) ** (1.0 / $grow)}]
for {set k 0} {$k < $grow} {incr k} {
    element resize -factor $f
    sim run -time 0.01 -quiet
}
sim run -time 0.1 -quiet
set t0 [clock microseconds]
set r [sim run -steps 1000 -quiet]
set us [expr {([clock microseconds] - $t0) / 1000.0}]
set m [dict get $r modules]
set kernel [expr {[info exists env(DEMLAB_KERNEL)] ? $env(DEMLAB_KERNEL) : "default"}]
puts [format "%d,%s,%d,%.1f,%.1f,%.1f,%d" $n $kernel [dict get $r contacts] $us \
    [expr {[dict get $m contacts-friction] * 1e6}] [expr {[dict get $m detection] * 1e6}] \
    [dict get $r rebuilds]]
