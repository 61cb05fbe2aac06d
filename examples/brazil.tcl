# The Brazilian test of a bonded disc (2D): the rock of examples/rock.tcl made by
# demlab::sample in a circle (held by a drum while it is compacted and bonded), then squeezed
# across a diameter between two rigid platens moving towards each other at a constant rate.
# The disc splits along the loaded diameter; the indirect tensile strength is
#   sigma_t = 2 F / (pi D t)
# with F the peak platen force and D the diameter, t = 1 (forces are per unit thickness in 2D).
# Every few steps it writes the platens' mean force and the cracks by mode to a CSV table; at the
# end it prints the peak force, sigma_t and the cracks at the peak, and returns them as a dict.
#
#   build/demlab examples/brazil.tcl ?file.csv? ?-short? ?-rate 1/s? ?-kscale k? ?-sscale s?
#
# -short: a smaller disc (the test suite's form). -rate: the platens' closing speed over the
# diameter (default 4/s, 10/s short). The run stops when the force has fallen below 60 % of the
# peak after it, or at 2 % of the diameter.

source [file join [file dirname [info script]] rock.tcl]

array set opt {-short 0 -rate {} -kscale 1 -sscale 1 -seed 1 -csv brazil.csv}
rock::parseArgs opt $argv
set rate [expr {$opt(-rate) ne {} ? $opt(-rate) : ($opt(-short) ? 10.0 : 4.0)}]
set R [expr {$opt(-short) ? 0.005 : 0.01}]

rock::scene 2
rock::cement $opt(-kscale) $opt(-sscale)
set made [rock::sample [list sphere {0 0} $R] -seed $opt(-seed)]
lassign [rock::extent sample 1] lo hi
lassign [rock::extent sample 0] left right
set D [expr {$hi - $lo}]
set v [expr {$rate * $D / 2}]
set bottom [wall add plane -normal {0 1} -point [list 0 $lo] -material plate -velocity [list 0 $v]]
set top [wall add plane -normal {0 -1} -point [list 0 $hi] -material plate -velocity [list 0 [expr {-$v}]]]

set interval [expr {($opt(-short) ? 4e-5 : 1e-5) / $rate}]
set fh [open $opt(-csv) w]
puts $fh "closure,force_N_per_m,broken,tension,shear"
set peak 0
set peakCracks 0
set start [clock milliseconds]
set t0 [sim time]
while {1} {
    sim run -time $interval -quiet -progress 0
    set closure [expr {$rate * ([sim time] - $t0)}]
    set force [expr {([lindex [wall get $top -force] 1] - [lindex [wall get $bottom -force] 1]) / 2}]
    lassign [rock::cracks] tension shear
    puts $fh [join [list $closure $force [expr {$tension + $shear}] $tension $shear] ,]
    if {$force > $peak} {
        set peak $force
        set peakCracks [expr {$tension + $shear}]
    }
    if {$force < 0.6 * $peak || $closure > 0.02} break
}
close $fh
set sigma [expr {2 * $peak / (acos(-1) * $D)}]
lassign [rock::cracks] tension shear
# Where the cracks are: the share of the breaks within a fifth of the diameter of the loaded
# (vertical) diameter, against the share of the disc's area there (a uniform spread).
set near 0
foreach b [bond breaks] {
    if {abs([lindex [dict get $b point] 0] - ($left + $right) / 2) < 0.1 * $D} {incr near}
}
set band [expr {0.1 * $D / ($D / 2)}]
set uniform [expr {(2 * asin($band) + sin(2 * asin($band))) / acos(-1)}]
set central [expr {$tension + $shear ? double($near) / ($tension + $shear) : 0}]
puts [format "brazil: %d discs, %d bonds, D %.4g mm; peak force %.4g kN/m, sigma_t = 2F/(pi D) = %.4g MPa (bond tensile strength %.3g MPa); %d cracks at the peak, %d tension and %d shear at the end, %.0f %% of them within D/10 of the loaded diameter (%.0f %% of the area); %.1f s; table in %s" \
    [dict get $made elements] [dict get $made bonds] [expr {$D * 1e3}] [expr {$peak / 1e3}] \
    [expr {$sigma / 1e6}] [expr {$opt(-sscale) * $rock::strength / 1e6}] $peakCracks $tension $shear \
    [expr {100 * $central}] [expr {100 * $uniform}] \
    [expr {([clock milliseconds] - $start) / 1000.0}] $opt(-csv)]
dict create elements [dict get $made elements] bonds [dict get $made bonds] diameter $D \
    peakforce $peak tensile $sigma peakcracks $peakCracks tension $tension shear $shear \
    central $central uniform $uniform
