# What the benchmark scripts that demlab runs share (bench_shapes.tcl, peer_clumps.tcl,
# peer_polyhedra.tcl): sourced by them from their own folder.

# Returns the CPU time (user + system, s) this process has used, from /proc/self/stat (fields
# 14 and 15, in clock ticks of 1/100 s).
proc cpuSeconds {} {
    set f [open /proc/self/stat]
    set fields [split [read $f]]
    close $f
    expr {([lindex $fields 13] + [lindex $fields 14]) / 100.0}
}

# Starts a new scene with the benchmarks' material "grain" (2500 kg/m^3, E 5e6 Pa, nu 0.3,
# restitution 0.5, friction 0.5) and gravity.
proc benchScene {} {
    sim new
    material add grain -density 2500 -young 5e6 -poisson 0.3 -restitution 0.5 -friction 0.5
    behavior add gravity
}

# Adds the four side walls (planes) of the square 0 < x, y < side, facing in.
proc addSideWalls {side} {
    foreach {n p} [list {1 0 0} {0 0 0} {-1 0 0} [list $side 0 0] {0 1 0} {0 0 0} {0 -1 0} [list 0 $side 0]] {
        wall add plane -normal $n -point $p
    }
}
