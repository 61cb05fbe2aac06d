# A silo (3D): a flat-bottomed cylinder (a drum wall) standing on an orifice plate (a finite wall
# with a circular hole), filled with grains that settle on a shutter under the hole; the shutter
# is taken away and the grains discharge through the orifice into a sink below. The sink's
# mass against time is the discharge; its steady slope is the mass flow rate W, which Beverloo's
# law predicts: W = C rho_b sqrt(g) (D - k d)^(5/2), C about 0.58 and k about 1.5, rho_b the
# bulk density of the fill, D the orifice's diameter, d the grains' (scripts/beverloo-study fits
# C and k over several D).
#
#   build/demlab examples/silo.tcl ?-D n? ?-height n? ?-time s? ?-csv file? ?-frames dir?
#                                  ?-refill 0|1? ?-friction mu? ?-short?
#
# -D: the orifice's diameter in grain diameters (default 6); -height: the fill's height in grain
# diameters (default 20); the silo's diameter is 2.5 D + 5 d, so its wall does not matter.
# -time: how long it discharges (s, default 1.5). -csv: where the series goes (default silo.csv:
# time, the sink's mass and count, the grains left). -frames: a folder for frames (side view,
# cut open; none by default). -refill 1: an inlet on top keeps the fill's height (the rate at
# Beverloo's prediction). -friction: the grains' (and walls') friction coefficient (default 0.5).
# -short: a small silo for a fraction of a second (the test suite's form).
# Returns a dict: d D rhob height grains W (kg/s, from the steady slope) Wbev (Beverloo with
# C = 0.58, k = 1.5) removed (sink mass, kg) lost (mass gone from the silo, kg) inflight (below
# the plate, not yet removed, kg) and the series' columns time and mass.

set nD 6.0
set nH 20.0
set tEnd 1.5
set csv silo.csv
set frames ""
set refill 0
set short 0
set mu 0.5
for {set i 0} {$i < [llength $argv]} {incr i} {
    set a [lindex $argv $i]
    switch -- $a {
        -short {set short 1}
        -D {set nD [lindex $argv [incr i]]}
        -height {set nH [lindex $argv [incr i]]}
        -time {set tEnd [lindex $argv [incr i]]}
        -csv {set csv [lindex $argv [incr i]]}
        -frames {set frames [lindex $argv [incr i]]}
        -refill {set refill [lindex $argv [incr i]]}
        -friction {set mu [lindex $argv [incr i]]}
        default {error "silo.tcl: unknown argument \"$a\""}
    }
}
if {$short} {
    set nH 6.0
    set tEnd 0.35
}

set r 0.0025                        ;# mean grain radius, m (radii uniform within +-10 %)
set d [expr {2 * $r}]
set rho 2500.0
set g 9.81
set D [expr {$nD * $d}]             ;# orifice diameter, m
set R [expr {(2.5 * $D + 5 * $d) / 2}]  ;# silo radius, m
set H [expr {$nH * $d}]             ;# fill height, m
set top [expr {2.6 * $H + 4 * $d}]  ;# the silo's height: room for the loose pack

sim new -dim 3
material add grain -density $rho -young 5e6 -poisson 0.3 -restitution 0.5 -friction $mu
behavior add gravity -g [list 0 0 [expr {-$g}]]
wall add drum -name silo -point [list 0 0 [expr {$top / 2}]] -axis {0 0 1} -radius $R \
    -halflength [expr {$top / 2}]
wall add finite -name plate -point {0 0 0} -normal {0 0 1} -axis {1 0 0} \
    -halfextents [list [expr {$R + $d}] [expr {$R + $d}]] -hole [expr {$D / 2}]
# The shutter: a plate a grain's radius under the orifice, taken away to start the discharge.
wall add finite -name shutter -point [list 0 0 [expr {-$r}]] -normal {0 0 1} -axis {1 0 0} \
    -halfextents [list $D $D]
# Half the default fraction of the critical step: the fill falls onto itself at up to 2 m/s,
# and soft grains hit that hard for fewer than ten steps at the default create energy.
sim timestep auto -fraction 0.1

# The fill: a loose random pack in the silo's square of the right height (solid fraction 0.25;
# it settles to about 0.6), the grains outside the cylinder taken out, then settled.
set rmax [expr {1.1 * $r}]
set loose [expr {$H * 0.6 / 0.25 + 2 * $d}]
set ids [pack random -region [list box [list [expr {-$R}] [expr {-$R}] $rmax] \
    [list $R $R [expr {$rmax + $loose}]]] -radius [list uniform [expr {0.9 * $r}] $rmax] \
    -fraction 0.25 -seed 1]
set outside {}
foreach id $ids {
    lassign [element get $id -position] x y
    if {hypot($x, $y) > $R - $rmax} {lappend outside $id}
}
element remove {*}$outside
set grains [element count]
# Settled when the grains' mean speed is about 1 mm/s.
set mass0 [dict get [query packing -region [list box [list [expr {-2 * $R}] [expr {-2 * $R}] -1] \
    [list [expr {2 * $R}] [expr {2 * $R}] [expr {2 * $top}]]]] mass]
set settled [demlab::settle -energy [expr {0.5 * $mass0 * 1e-6}] -chunk 500 \
    -maxsteps [expr {$short ? 8000 : 40000}]]
# The discharge at the default fraction: the grains leave at a fraction of 1 m/s, and the
# automatic step keeps within half what the loaded bed's contacts allow.
sim timestep auto

# The bulk density: the solid fraction of a box inside the cylinder, between a quarter and three
# quarters of the fill's height (the fill's height from its solid volume and that fraction).
set half [expr {$R / sqrt(2) - $d}]
set probe [query packing -region [list box [list [expr {-$half}] [expr {-$half}] [expr {0.25 * $H}]] \
    [list $half $half [expr {0.75 * $H}]]]]
set phi [dict get $probe fraction]
set rhob [expr {$phi * $rho}]
set height [expr {$mass0 / ($rhob * acos(-1) * $R * $R)}]
puts [format "silo: %d grains, d = %.3g m, D = %.3g m (%.3g d), silo diameter %.3g m, fill %.3g m,\
    solid fraction %.3f, bulk density %.4g kg/m^3; settled in %d steps (%s)" $grains $d $D $nD \
    [expr {2 * $R}] $height $phi $rhob [dict get $settled steps] \
    [expr {[dict get $settled settled] ? "at rest" : "not yet at rest"}]]

# Beverloo's prediction with the published constants.
set Wbev [expr {0.58 * $rhob * sqrt($g) * pow($D - 1.5 * $d, 2.5)}]
if {$refill} {
    # Grains poured in at the predicted rate over the fill keep its height.
    set zin [expr {$height + 3 * $d}]
    inlet add refill -region [list cylinder [list 0 0 [expr {$zin + 2 * $d}]] {0 0 1} \
        [expr {$R - 2 * $rmax}] [expr {2 * $d}]] -radius [list uniform [expr {0.9 * $r}] $rmax] \
        -massrate $Wbev -velocity {0 0 -0.2} -seed 2
}

# Open: the sink takes every grain whose centre falls 10 grain diameters under the plate.
set t0 [sim time]
wall remove shutter
sink add out -point [list 0 0 [expr {-10 * $d}]] -normal {0 0 1}
set flow [series every -time 0.01 -file $csv -quantities {time sink:out:mass sink:out:count elements}]
if {$frames ne ""} {
    snapshot every -time [expr {$tEnd / 30}] -dir $frames -size 640x800 -color speed \
        -range {0 0.6} -position [list 0 [expr {-12 * $R}] [expr {0.45 * $top}]] \
        -lookat [list 0 0 [expr {0.3 * $top}]] -fov 25 -clip {0 0 0 0 -1 0} -timestamp 1
}
sim run -time $tEnd -quiet -progress 0
if {$frames ne ""} {snapshot off}
set times [dict get [series get $flow] time]
set masses [dict get [series get $flow] sink:out:mass]
series off $flow

# The flow rate: the least-squares slope of the sink's mass against time, from when the first
# grains have reached the sink and the flow has settled (0.25 s after opening; 0.15 s short).
set tFrom [expr {$t0 + ($short ? 0.15 : 0.25)}]
set n 0
set st 0.0; set sm 0.0; set stt 0.0; set stm 0.0
foreach t $times m $masses {
    if {$t < $tFrom} continue
    incr n
    set st [expr {$st + $t}]; set sm [expr {$sm + $m}]
    set stt [expr {$stt + $t * $t}]; set stm [expr {$stm + $t * $m}]
}
set W [expr {$n > 2 ? ($n * $stm - $st * $sm) / ($n * $stt - $st * $st) : 0.0}]

# Mass accounts: what the sink took is what the scene lost (less what the inlet gave), and what
# the silo lost is that plus what is falling between the plate and the sink.
set everywhere [list box [list [expr {-2 * $R}] [expr {-2 * $R}] [expr {-20 * $d}]] \
    [list [expr {2 * $R}] [expr {2 * $R}] [expr {2 * $top}]]]
set above [list box [list [expr {-2 * $R}] [expr {-2 * $R}] 0] [list [expr {2 * $R}] [expr {2 * $R}] [expr {2 * $top}]]]
set given [expr {$refill ? [inlet get refill -mass] : 0.0}]
set massNow [dict get [query packing -region $everywhere] mass]
set inSilo [dict get [query packing -region $above] mass]
set removed [sink get out -mass]
puts [format "W = %.4g kg/s from the steady slope (Beverloo, C = 0.58, k = 1.5: %.4g kg/s);\
    removed %d grains, %.4g kg" $W $Wbev [sink get out -count] $removed]
dict create d $d D $D rhob $rhob height $height grains $grains W $W Wbev $Wbev \
    removed $removed lost [expr {$mass0 + $given - $massNow}] \
    siloLost [expr {$mass0 + $given - $inSilo}] inflight [expr {$massNow - $inSilo}] \
    time $times mass $masses
