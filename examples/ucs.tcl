# Unconfined compression of a bonded sample (the thesis's figure 1-8; Potyondy and Cundall's
# parallel-bonded rock): the rock of examples/rock.tcl made by demlab::sample in a box (a random
# dense pack of a size distribution, compacted to a low stress, bonded), squeezed between two
# rigid platens moving towards each other at a constant strain rate, no side walls. Every few
# steps it reads the axial stress (the platens' mean force over the sample's width, per unit
# thickness in 2D; over its cross-section in 3D), the axial strain (the change of the distance
# between the mean centres of the elements on the top and bottom faces, over its initial value),
# the lateral strain (the same across the sides) and the cracks (broken bonds) by mode, and writes
# them as a CSV table. At the end it prints the peak strength, Young's modulus and Poisson's
# ratio (least-squares slopes of the stress and of the lateral strain against the axial
# strain between 25 % and 50 % of the peak, before it) and the cracks at the peak, and returns
# them as a dict.
#
#   build/demlab examples/ucs.tcl ?file.csv? ?-short? ?-dim 2|3? ?-rate 1/s? ?-kscale k?
#                                 ?-sscale s? ?-cscale c? ?-seed n? ?-width m? ?-export prefix?
#
# -short: a smaller sample at a faster rate (the test suite's form). -rate: the strain rate
# (default 4/s, 10/s short); -kscale, -sscale: factors on the bonds' stiffness and strength;
# -cscale: on the contacts' modulus; -width: the sample's width in m (the height is twice
# it); -export: write the sample and its loading for another code before loading it
# (rock::export; scripts/peer-bond runs yade on them).
# At 4/s the sample shortens by a few 1e-5 of its height per P-wave transit, a few percent of
# the strain at the peak: quasi-static (doc/verification.md compares a run at half the rate).
# The run stops when the stress has fallen below 60 % of the peak after it, or at 2 % strain.

source [file join [file dirname [info script]] rock.tcl]

array set opt {-short 0 -dim 2 -rate {} -kscale 1 -sscale 1 -cscale 1 -seed 1 -csv ucs.csv
    -width {} -export {}}
rock::parseArgs opt $argv
set d $opt(-dim)
set rate [expr {$opt(-rate) ne {} ? $opt(-rate) : ($opt(-short) ? 10.0 : 4.0)}]
# Width by height (2D); 3D a square prism of that cross-section, one width deep.
set W [expr {$opt(-short) ? ($d == 2 ? 0.006 : 0.004) : ($d == 2 ? 0.016 : 0.005)}]
if {$opt(-width) ne {}} {set W $opt(-width)}
set H [expr {2 * $W}]
set axis [expr {$d - 1}]

rock::scene $d $opt(-cscale)
rock::cement $opt(-kscale) $opt(-sscale)
set region [expr {$d == 2 ? [list box {0 0} [list $W $H]] : [list box {0 0 0} [list $W $W $H]]}]
set made [rock::sample $region -seed $opt(-seed)]
set bonds [dict get $made bonds]

# The faces: the elements within the largest radius of each extreme.
for {set k 0} {$k < $d} {incr k} {rock::tagFaces sample $k $rock::rmax}
lassign [rock::extent sample $axis] lo hi
set area 1.0
for {set k 0} {$k < $axis} {incr k} {
    lassign [rock::extent sample $k] a b
    set area [expr {$area * ($b - $a)}]
}
set h0 [expr {[rock::meanOf hi$axis $axis] - [rock::meanOf lo$axis $axis]}]
set w0 [expr {[rock::meanOf hi0 0] - [rock::meanOf lo0 0]}]
set v [expr {$rate * ($hi - $lo) / 2}]
set n [lrepeat $d 0]
set bottom [wall add plane -normal [lreplace $n $axis $axis 1] -point [lreplace $n $axis $axis $lo] \
    -material plate -velocity [lreplace $n $axis $axis $v]]
set top [wall add plane -normal [lreplace $n $axis $axis -1] -point [lreplace $n $axis $axis $hi] \
    -material plate -velocity [lreplace $n $axis $axis [expr {-$v}]]]

set strainEnd 0.02
set interval [expr {($opt(-short) ? 4e-5 : 1e-5) / $rate}]   ;# a row every 1e-5 of strain
if {$opt(-export) ne {}} {
    rock::export $opt(-export) axis $axis rate $rate velocity $v lo $lo hi $hi area $area \
        h0 $h0 interval $interval strain_end $strainEnd \
        lo_face [element list -tag lo$axis] hi_face [element list -tag hi$axis]
}
set fh [open $opt(-csv) w]
puts $fh "strain,lateral_strain,stress_Pa,broken,tension,shear"
set peak 0
set peakStrain 0
set peakCracks 0
set curve {}
set start [clock milliseconds]
set cpu0 [rock::cpuSeconds]
set steps0 [sim time -steps]
while {1} {
    sim run -time $interval -quiet -progress 0
    set strain [expr {1 - ([rock::meanOf hi$axis $axis] - [rock::meanOf lo$axis $axis]) / $h0}]
    set lateral [expr {([rock::meanOf hi0 0] - [rock::meanOf lo0 0]) / $w0 - 1}]
    # Force on each wall from the elements: the top is pushed up, the bottom down.
    set stress [expr {([lindex [wall get $top -force] $axis] - [lindex [wall get $bottom -force] $axis]) / 2 / $area}]
    lassign [rock::cracks] tension shear
    puts $fh [join [list $strain $lateral $stress [expr {$tension + $shear}] $tension $shear] ,]
    lappend curve $strain $stress $lateral
    if {$stress > $peak} {
        set peak $stress
        set peakStrain $strain
        set peakCracks [expr {$tension + $shear}]
    }
    if {$stress < 0.6 * $peak || $strain > $strainEnd} break
}
close $fh
set seconds [expr {([clock milliseconds] - $start) / 1000.0}]
set cpu [expr {$cpu0 eq {} ? {} : [rock::cpuSeconds] - $cpu0}]
set steps [expr {[sim time -steps] - $steps0}]

# Least-squares slopes against the axial strain over the rows between 25 % and 50 % of the
# peak, before it.
set xs {}
set ys {}
set ls {}
foreach {e s l} $curve {
    if {$e > $peakStrain} break
    if {$s >= 0.25 * $peak && $s <= 0.5 * $peak} {
        lappend xs $e
        lappend ys $s
        lappend ls $l
    }
}
# Returns the least-squares slope of ys against xs (0 with fewer than two points).
proc slope {xs ys} {
    set n [llength $xs]
    if {$n < 2} {return 0}
    set mx [expr {[tcl::mathop::+ {*}$xs] / $n}]
    set my [expr {[tcl::mathop::+ {*}$ys] / $n}]
    set sxy 0.0
    set sxx 0.0
    foreach x $xs y $ys {
        set sxy [expr {$sxy + ($x - $mx) * ($y - $my)}]
        set sxx [expr {$sxx + ($x - $mx) ** 2}]
    }
    expr {$sxy / $sxx}
}
set modulus [slope $xs $ys]
set poisson [slope $xs $ls]
lassign [rock::cracks] tension shear
puts [format "ucs (%dD): %d elements, %d bonds, fraction %.3f, locked-in stress %.3g MPa (%.2g %% of the bond strength); rate %g/s: peak %.4g MPa at strain %.4g (%d cracks then); E %.4g GPa, Poisson's ratio %.3f; at the end %d tension, %d shear cracks; %d steps in %.1f s (%.3g us/step); table in %s" \
    $d [dict get $made elements] $bonds [dict get $made fraction] [expr {[dict get $made lockedin] / 1e6}] \
    [expr {100 * [dict get $made lockedin] / ($opt(-sscale) * $rock::strength)}] $rate \
    [expr {$peak / 1e6}] $peakStrain $peakCracks [expr {$modulus / 1e9}] $poisson $tension $shear \
    $steps $seconds [expr {1e6 * $seconds / max(1, $steps)}] $opt(-csv)]
dict create elements [dict get $made elements] bonds $bonds fraction [dict get $made fraction] \
    lockedin [dict get $made lockedin] stress [dict get $made stress] peak $peak \
    peakstrain $peakStrain peakcracks $peakCracks modulus $modulus poisson $poisson \
    tension $tension shear $shear rate $rate steps $steps seconds $seconds cpu $cpu
