# A hopper (2D): a source fills a V-shaped hopper of walls from above while a sink below the
# orifice takes the grains that have left; the mass through the sink against time is the
# discharge, written as a time series, and its steady slope the mass flow rate (per metre of
# depth: the scene is 2D). The source stops at a target mass; the flow then goes on until the
# hopper is empty.
#
#   build/demlab examples/hopper.tcl ?csv? ?-short?
#
# csv: where the series goes (default hopper.csv). -short: the same scene for a few hundredths
# of a second (the test suite's form).

set csv hopper.csv
set short 0
foreach a $argv {
    if {$a eq "-short"} {set short 1} else {set csv $a}
}

set D 0.012        ;# orifice width, m (six grain diameters)
set H 0.04         ;# height of the V, m
set W 0.04         ;# half width of the hopper, m
set tEnd [expr {$short ? 0.03 : 1.5}]

sim new -dim 2
material add glass -density 2500 -young 5e6 -poisson 0.3 -restitution 0.5 -friction 0.5
behavior add gravity -g {0 -9.81}
sim timestep auto

# Adds a finite wall (a segment in 2D) from (ax, ay) to (bx, by).
proc segment {name ax ay bx by} {
    set len [expr {hypot($bx - $ax, $by - $ay)}]
    set centre [list [expr {($ax + $bx) / 2.0}] [expr {($ay + $by) / 2.0}]]
    set normal [list [expr {-($by - $ay) / $len}] [expr {($bx - $ax) / $len}]]
    wall add finite -name $name -point $centre -normal $normal -halfextents [expr {$len / 2}]
}
segment left [expr {-$W}] $H [expr {-$D / 2}] 0
segment right $W $H [expr {$D / 2}] 0
segment leftside [expr {-$W}] $H [expr {-$W}] 0.2
segment rightside $W $H $W 0.2

# The feed: 20 kg/s a metre of depth until 8 kg/m are in, then the hopper empties; the sink
# 3 cm below the orifice.
inlet add feed -region [list box [list [expr {-$W + 0.003}] 0.1] [list [expr {$W - 0.003}] 0.18]] \
    -radius {uniform 0.0008 0.0012} -massrate 20 -mass 8 -velocity {0 -0.5} -jitter 0.05 -seed 1
sink add out -point {0 -0.03} -normal {0 1}

set flow [series every -time 0.01 -file $csv \
    -quantities {time sink:out:mass sink:out:count inlet:feed:mass elements}]
sim run -time $tEnd -quiet -progress 0

# The flow rate: the slope of the sink's mass against time where it is steady (between a
# quarter and three quarters of what the source gave).
set given [inlet get feed -mass]
set pts {}
foreach t [dict get [series get $flow] time] m [dict get [series get $flow] sink:out:mass] {
    if {$m > 0.25 * $given && $m < 0.75 * $given} {lappend pts $t $m}
}
if {[llength $pts] >= 6} {
    set n [expr {[llength $pts] / 2}]
    set st 0.0; set sm 0.0; set stt 0.0; set stm 0.0
    foreach {t m} $pts {
        set st [expr {$st + $t}]; set sm [expr {$sm + $m}]
        set stt [expr {$stt + $t * $t}]; set stm [expr {$stm + $t * $m}]
    }
    set rate [expr {($n * $stm - $st * $sm) / ($n * $stt - $st * $st)}]
    puts [format "mass flow rate %.3g kg/s per metre of depth (orifice %.3g m)" $rate $D]
} else {
    puts "no steady discharge yet at t = [sim time] s"
}
puts "inserted [inlet get feed -count] grains ([format %.4g $given] kg/m),\
    discharged [sink get out -count] ([format %.4g [sink get out -mass]] kg/m); series in $csv"
series off
list [inlet get feed -count] [sink get out -count] [element count]
