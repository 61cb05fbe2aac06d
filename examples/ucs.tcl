# Unconfined compression of a bonded sample (2D, after MIMES's bonded samples and Potyondy and
# Cundall's parallel-bonded rock): a hexagonal pack of equal discs in a box (a random dense pack
# needs a generator that compresses and relaxes, not written yet), bonded to every neighbour by
# parallel bonds with scattered strengths, squeezed between two platens moving
# towards each other at a constant strain rate, no side walls. Every few steps it reads the axial
# stress (the platens' mean force over the sample's width, per unit thickness), the axial strain
# (the change of the sample's height, between the mean centres of its top and bottom rows, over
# the initial one), the lateral strain (the same across its sides) and the number of broken bonds by mode, and
# writes them as a CSV table; at the end it prints the peak strength, the modulus and Poisson's
# ratio (secant, from 0 to half the peak) and the cracks at the peak.
#
#   build/demlab examples/ucs.tcl ?file.csv? ?-short?
#
# -short: a smaller sample (the test suite's form). The full form (about 900 discs) takes a few minutes on a busy 2-core machine. The platens move at a speed far below the
# sample's wave speed, so the loading is quasi-static (the sample crosses many times per percent
# of strain); bonds carry no damping, the contacts' restitution damps the rest.

set csv ucs.csv
set short 0
foreach a $argv {
    if {$a eq "-short"} {set short 1} else {set csv $a}
}

set W [expr {$short ? 0.008 : 0.02}]   ;# sample width and height, m
set H [expr {2 * $W}]
set r 0.0005                           ;# disc radius, m
set strainRate [expr {$short ? 100.0 : 20.0}]                   ;# 1/s: each platen at strainRate H / 2
set strainEnd 0.004                  ;# stop at this axial strain
set rows [expr {$short ? 20 : 60}]                           ;# table rows over the run

sim new -dim 2
material add rock -density 2600 -young 2e10 -poisson 0.25 -restitution 0.3 -friction 0.5
# Rigid platens: the sample's stiffness, not the platens' Hertz contacts, is what is measured.
material add plate -rigid 1 -density 7800 -poisson 0.3 -restitution 0.3 -friction 0.5
# A stiff disc-platen pair: the load reaches the sample without deep platen overlaps.
law coefficients rock plate -young 1e13
pack lattice -region [list box {0 0} [list $W $H]] -radius $r -kind hex
# Parallel bonds: modulus E_c = kn (Ri + Rj) = 2 GPa, kn = ks, strengths 2 MPa +- 20 %.
set kn [expr {2e9 / (2 * $r)}]
bond model parallel cement -kn $kn -ks $kn -tensile 2e6 -shear 2e6 -scatter 0.2 -seed 3
set nBonds [llength [bond add -model cement -gap [expr {0.01 * $r}]]]
# Platens just outside the sample's extremes, moving towards each other.
set lo 1e9
set hi -1e9
foreach id [element list] {
    set y [lindex [element get $id -position] 1]
    set r [element get $id -radius]
    set lo [expr {min($lo, $y - $r)}]
    set hi [expr {max($hi, $y + $r)}]
}
set height [expr {$hi - $lo}]
# The sample's own dimensions: the mean heights of its top and bottom rows, the mean abscissae of
# its left and right columns (the platens' contacts are not part of the strain).
set left 1e9
set right -1e9
foreach id [element list] {
    set x [lindex [element get $id -position] 0]
    set left [expr {min($left, $x)}]
    set right [expr {max($right, $x)}]
}
foreach id [element list] {
    lassign [element get $id -position] x y
    if {$y > $hi - 1.5 * $r} {element tag toprow $id}
    if {$y < $lo + 1.5 * $r} {element tag bottomrow $id}
    if {$x < $left + 0.5 * $r} {element tag leftcol $id}
    if {$x > $right - 0.5 * $r} {element tag rightcol $id}
}
# Returns the mean coordinate k of the elements carrying tag.
proc meanOf {tag k} {
    set sum 0.0
    set ids [element list -tag $tag]
    foreach id $ids {set sum [expr {$sum + [lindex [element get $id -position] $k]}]}
    expr {$sum / [llength $ids]}
}
set h0 [expr {[meanOf toprow 1] - [meanOf bottomrow 1]}]
set w0 [expr {[meanOf rightcol 0] - [meanOf leftcol 0]}]
set v [expr {$strainRate * $height / 2}]
set bottom [wall add plane -normal {0 1} -point [list 0 $lo] -material plate -velocity [list 0 $v]]
set top [wall add plane -normal {0 -1} -point [list 0 $hi] -material plate -velocity [list 0 [expr {-$v}]]]

set total [expr {$strainEnd / $strainRate}]
set fh [open $csv w]
puts $fh "strain,lateral_strain,stress_Pa,broken,tension,shear"
set peak 0
set peakStrain 0
set peakCracks 0
set curve {}
for {set k 1} {$k <= $rows} {incr k} {
    sim run -time [expr {$total / $rows}] -quiet -progress 0
    set strain [expr {1 - ([meanOf toprow 1] - [meanOf bottomrow 1]) / $h0}]
    set lateral [expr {([meanOf rightcol 0] - [meanOf leftcol 0]) / $w0 - 1}]
    set fTop [lindex [wall get $top -force] 1]
    set fBottom [lindex [wall get $bottom -force] 1]
    # Force on each wall from the elements: the top is pushed up, the bottom down.
    set stress [expr {($fTop - $fBottom) / 2 / $W}]
    set c [bond count]
    puts $fh [join [list $strain $lateral $stress [dict get $c broken] [dict get $c tension] [dict get $c shear]] ,]
    lappend curve $strain $stress $lateral
    if {$stress > $peak} {
        set peak $stress
        set peakStrain $strain
        set peakCracks [dict get $c broken]
    }
}
close $fh
# Secant modulus from the origin to the first point at half the peak.
# Poisson's ratio: minus the lateral over the axial strain there.
set modulus 0
set poisson 0
foreach {e s l} $curve {
    if {$s >= $peak / 2} {
        set modulus [expr {$s / $e}]
        set poisson [expr {-$l / $e}]
        break
    }
}
set c [bond count]
puts [format "ucs: %d discs, %d bonds; peak %.4g MPa at strain %.4g (%d cracks then); modulus %.4g GPa, Poisson's ratio %.3g; at the end %d broken (%d tension, %d shear); table in %s" \
    [element count] $nBonds [expr {$peak / 1e6}] $peakStrain $peakCracks [expr {$modulus / 1e9}] $poisson \
    [dict get $c broken] [dict get $c tension] [dict get $c shear] $csv]
list $peak $modulus $poisson [dict get $c broken]
