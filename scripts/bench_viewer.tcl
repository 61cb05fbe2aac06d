# The body of scripts/bench-viewer. argv: grains steps repeats.
lassign $argv grains steps repeats
package require Tk
wm withdraw .
sim new
material add glass -density 2500 -young 5e6 -poisson 0.3 -restitution 0.5 -friction 0.5
behavior add gravity -g {0 0 -9.81}
wall add plane -point {0 0 0} -normal {0 0 1}
set side [expr {0.002 * pow($grains, 1.0 / 3)}]
pack lattice -region [list box {0 0 0} [list $side $side $side]] -radius 0.001
sim timestep auto
sim run -steps 200 -quiet -progress 0  ;# past the first steps' set-up
# The redraws' own time, summed by a wrapper around the watcher's procedure.
proc wrapTick {} {
    if {[info commands ::demlab::viewer::TimedTick] ne ""} return
    rename ::demlab::viewer::Tick ::demlab::viewer::TimedTick
    proc ::demlab::viewer::Tick {} {
        set t0 [clock microseconds]
        ::demlab::viewer::TimedTick
        set ::tickUs [expr {$::tickUs + [clock microseconds] - $t0}]
    }
}
# Wall-clock overhead against the run without a window just before it (noisy on a shared
# machine: compare the redraw share, the watcher's own time over the run's).
puts "grains,fps,steps,seconds,frames,overhead_percent,redraw_share_percent,ms_per_frame"
set base {}
for {set r 0} {$r < $repeats} {incr r} {
    foreach fps {0 2 5 15} {
        if {$fps > 0} {viewer open -size 640x480 -fps $fps; update; wrapTick}
        set ::tickUs 0
        set f0 [expr {$fps > 0 ? $::demlab::viewer::frames : 0}]
        set t0 [clock microseconds]
        sim run -steps $steps -quiet -progress 0
        set s [expr {([clock microseconds] - $t0) / 1e6}]
        set frames [expr {$fps > 0 ? $::demlab::viewer::frames - $f0 : 0}]
        if {$fps > 0} {viewer close; update}
        if {$fps == 0} {set base $s}
        set over [expr {100.0 * ($s - $base) / $base}]
        set share [expr {100.0 * $::tickUs / 1e6 / $s}]
        set per [expr {$frames ? $::tickUs / 1e3 / $frames : 0}]
        puts [format "%d,%d,%d,%.3f,%d,%.1f,%.1f,%.1f" [dict get [sim info] elements] $fps $steps \
                  $s $frames $over $share $per]
    }
}
exit
