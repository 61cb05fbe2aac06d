# A drained triaxial test (3D) of frictional spheres in a cuboid of six frictionless plane walls:
# the four lateral walls held at the confining stress sigma3 by servos (wall servo), an
# isotropic consolidation to sigma3, then the top platen driven down at a constant strain rate
# while the bottom one stays. Every chunk of steps it reads the axial strain (from the platens'
# positions), sigma1 (the platen's force over the current cross-section), sigma3 on each lateral
# wall (its force over its current loaded area) and the volumetric strain (from the six walls'
# positions, compression positive), and writes them as a CSV table. At the end it prints the
# peak deviatoric stress q = sigma1 - sigma3, the peak friction angle
# phi = asin((s1 - s3) / (s1 + s3)) and the inertial number of the shear, and returns them with
# the curve as a dict.
#
#   build/demlab examples/triaxial.tcl ?file.csv? ?-short? ?-sample dense|loose? ?-seed n?
#                                      ?-count n? ?-rate 1/s? ?-strain e? ?-verbose?
#
# -sample dense: consolidated with the grains' friction off, so they pack densely (then set to
# -friction 0.5 for the shear); loose: consolidated with friction 5, which leaves a loose
# packing. -short: 343 grains to 10 % axial strain (the test suite's form, seconds); the full form
# 3000 grains to 20 %. -count, -rate (the axial strain rate), -strain (where the shear stops)
# override either. -verbose prints each wall's stress every chunk of the consolidation.
#
# The servos hold a force; the stress is that force over the wall's loaded area, which the
# other four walls bound and which changes as the sample deforms. The script recomputes each
# lateral wall's force target from its current area between chunks (wall servo again, which
# keeps the wall where it is). A chunk is 1e-3 of axial strain: the height shrinks by 1e-3 and
# the lateral span grows by less, so the area changes by less than 1e-3 of itself, a tenth of
# the 1 % the confinement is held to.

array set opt {-verbose 0 -short 0 -sample dense -seed 1 -count {} -rate {} -strain {} -csv triaxial.csv}
set args $argv
while {[llength $args]} {
    set args [lassign $args a]
    switch -- $a {
        -short {set opt(-short) 1}
        -verbose {set opt(-verbose) 1}
        -sample - -seed - -count - -rate - -strain {
            if {![llength $args]} {error "triaxial.tcl: $a needs a value" {} {DEMLAB ARGS}}
            set args [lassign $args opt($a)]
        }
        default {
            if {[string match -* $a]} {
                error "triaxial.tcl: unknown option \"$a\"" {} {DEMLAB OPTION}
            }
            set opt(-csv) $a
        }
    }
}
if {$opt(-sample) ni {dense loose}} {
    error "triaxial.tcl: bad sample \"$opt(-sample)\": must be dense or loose" {} {DEMLAB VALUE SAMPLE}
}
foreach o {-count -seed} {
    if {$opt($o) ne {} && !([string is wideinteger -strict $opt($o)] && $opt($o) > 0)} {
        error "triaxial.tcl: bad [string range $o 1 end] \"$opt($o)\": must be a positive integer" {} \
            [list DEMLAB VALUE [string toupper [string range $o 1 end]]]
    }
}
foreach o {-rate -strain} {
    if {$opt($o) ne {} && !([string is double -strict $opt($o)] && $opt($o) > 0 && $opt($o) < Inf)} {
        error "triaxial.tcl: bad [string range $o 1 end] \"$opt($o)\": must be a positive number" {} \
            [list DEMLAB VALUE [string toupper [string range $o 1 end]]]
    }
}

set N [expr {$opt(-count) ne {} ? $opt(-count) : ($opt(-short) ? 343 : 3000)}]
set strainEnd [expr {$opt(-strain) ne {} ? $opt(-strain) : ($opt(-short) ? 0.10 : 0.2)}]
set sigma3 1e5          ;# the confining stress, Pa
set r 0.001             ;# the mean radius, m (radii uniform in 0.8 r .. 1.2 r)
set rho 2650.0          ;# the grains' density, kg/m^3
set young 1e9           ;# their Young's modulus: the mean overlap at sigma3 is about 0.7 % of r
set mu 0.5              ;# their friction in the shear

sim new -dim 3
material add grain -density $rho -young $young -poisson 0.3 -restitution 0.3 \
    -friction [expr {$opt(-sample) eq "dense" ? 0.0 : 5.0}]
material add plate -density $rho -young $young -poisson 0.3 -restitution 0.3 -friction 0
law default hertz

# A cube holding the N grains as a gas at solid fraction 0.3.
set vGrain [expr {4.0 / 3 * acos(-1) * $r ** 3 * 1.04}]   ;# <r^3> for uniform 0.8..1.2 is 1.04 r^3
set L0 [expr {($N * $vGrain / 0.3) ** (1.0 / 3)}]
pack random -region [list box {0 0 0} [list $L0 $L0 $L0]] -radius [list uniform [expr {0.8 * $r}] [expr {1.2 * $r}]] \
    -count $N -seed $opt(-seed) -material grain -tags sample
set normals {}
foreach {name normal point} [list \
        xlo {1 0 0} {0 0 0} xhi {-1 0 0} [list $L0 0 0] \
        ylo {0 1 0} {0 0 0} yhi {0 -1 0} [list 0 $L0 0] \
        bottom {0 0 1} {0 0 0} top {0 0 -1} [list 0 0 $L0]] {
    wall add plane -name $name -normal $normal -point $point -material plate
    dict set normals $name $normal
}
set lateral {xlo xhi ylo yhi}
namespace eval triaxial {}
# A fixed step, 0.1 of the Rayleigh step (the critical estimate before any contact): the
# consolidation and the shear below count their chunks, rows and servo gains in steps. The
# automatic step would follow the contacts' stiffness as the sample is loaded (doc/design.md,
# "The time step"); before it did, 0.2 of the Rayleigh step (then the default) and 0.13 pumped
# energy into the tangential-rotational mode of this packing at sigma3 (overlaps about 0.7 % of
# r), and 0.1 did not.
sim timestep [expr {0.1 * [sim critical]}]
set dt [sim timestep]

# Returns the walls' positions as a dict: x0 x1 y0 y1 z0 z1.
proc triaxial::box {} {
    dict create x0 [lindex [wall get xlo -point] 0] x1 [lindex [wall get xhi -point] 0] \
        y0 [lindex [wall get ylo -point] 1] y1 [lindex [wall get yhi -point] 1] \
        z0 [lindex [wall get bottom -point] 2] z1 [lindex [wall get top -point] 2]
}
# Returns the loaded area of wall w (m^2) in the box b: the product of the other two spans.
proc triaxial::area {w b} {
    dict with b {}
    switch -- $w {
        xlo - xhi {expr {($y1 - $y0) * ($z1 - $z0)}}
        ylo - yhi {expr {($x1 - $x0) * ($z1 - $z0)}}
        default {expr {($x1 - $x0) * ($y1 - $y0)}}
    }
}
# Returns the normal stress the grains put on wall w (Pa, compression positive) in the box b.
proc triaxial::wallStress {w b} {
    global normals
    set f [wall get $w -force]
    set n [dict get $normals $w]
    set along 0.0
    foreach fk $f nk $n {set along [expr {$along - $fk * $nk}]}
    expr {$along / [triaxial::area $w $b]}
}

# The servo gain, bounded twice. The force a wall reads answers its own step: through its
# contacts' springs (stable for gain K dt < 2, K their stiffnesses in parallel, at most about
# one contact per (2r)^2 of wall, each Hertz's tangent stiffness 2 E* a at the mean force
# f = sigma3 (2r)^2; doc/design.md) and at once through their dampers (stable for
# gain x (their damping coefficients in parallel) < 1, whatever the step: with restitution 0.3
# on the walls this bound is the tighter, about ten times). A wall moving at v lags its target
# by v / gain of force, over 1 % of sigma3 at that gain while the dense sample dilates; so the
# walls' contacts get a restitution of 1 (law coefficients: no damper, not needed in a
# quasi-static test; the grains' own contacts keep theirs) and the gain is half the springs'
# bound, K counted as if every wall contact were in parallel with no grain behind (the grains
# behind are in series and soften it: the margin is larger).
set eStar [expr {$young / (2 * (1 - 0.3 ** 2))}]
set f [expr {$sigma3 * 4 * $r * $r}]
set delta [expr {(3 * $f / (4 * $eStar * sqrt($r))) ** (2.0 / 3)}]
set a [expr {sqrt($r * $delta)}]
set mass [expr {4.0 / 3 * acos(-1) * $rho * $r ** 3}]
set eWall 1.0
law coefficients grain plate -restitution $eWall
set beta [expr {log($eWall) / sqrt(log($eWall) ** 2 + acos(-1) ** 2)}]
# Returns the gain for walls of side L: half of either bound.
proc triaxial::gainFor {L} {
    global r eStar a beta mass dt
    set contactsOnWall [expr {$L * $L / (4 * $r * $r)}]
    set kWall [expr {$contactsOnWall * 2 * $eStar * $a}]
    set cWall [expr {$contactsOnWall * 2 * sqrt(5.0 / 6) * abs($beta) * sqrt(2 * $eStar * $a * $mass)}]
    expr {$cWall > 0 ? min(1.0 / ($kWall * $dt), 0.5 / $cWall) : 1.0 / ($kWall * $dt)}
}
set gain [triaxial::gainFor $L0]
# Holds each of the walls at sigma3 over its current area (see the comment at the top).
proc triaxial::servoAll {walls speed} {
    global sigma3 gain
    set b [triaxial::box]
    foreach w $walls {wall servo $w -stress $sigma3 -area [triaxial::area $w $b] -gain $gain -maxspeed $speed}
}

# Isotropic consolidation: five walls under servo (the bottom stays), in chunks, the targets
# following the areas, until every wall reads sigma3 within 1 % and the grains are at rest.
set consolSpeed [expr {0.02 * $L0 / (1000 * $dt)}]   ;# 2 % of the box per 1000 steps at most
set chunk 500
set consolSteps 0
set consolidated 0
for {set k 0} {$k < 400} {incr k} {
    triaxial::servoAll [list {*}$lateral top] $consolSpeed
    sim run -steps $chunk -quiet -progress 0
    incr consolSteps $chunk
    set b [triaxial::box]
    set worst 0
    foreach w [list {*}$lateral top bottom] {
        set worst [expr {max($worst, abs([triaxial::wallStress $w $b] / $sigma3 - 1))}]
    }
    set e [query energy]
    # (Translational only: a rattler free in its cage may spin on for long, and carries no
    # stress: its spin bounces back from a sticking contact, which damps it only by the dashpot.)
    set ek [dict get $e kinetic]
    if {$opt(-verbose)} {
        puts [format "consolidation %d: stresses %s kPa, kinetic %.3g J" $k \
            [lmap w [list {*}$lateral top bottom] {format %.1f [expr {[triaxial::wallStress $w $b] / 1e3}]}] $ek]
    }
    # At rest: the kinetic energy below 1e-5 of the work sigma3 does over a grain diameter on a face.
    if {$worst < 0.01 && $ek < 1e-5 * $sigma3 * 2 * $r * [triaxial::area top $b]} {
        set consolidated 1
        break
    }
}
material set grain -friction $mu
# A few chunks with the shear's friction before the platen moves.
for {set k 0} {$k < 4} {incr k} {
    triaxial::servoAll [list {*}$lateral top] $consolSpeed
    sim run -steps $chunk -quiet -progress 0
    incr consolSteps $chunk
}
set b0 [triaxial::box]
dict with b0 {}
set gain [triaxial::gainFor [expr {sqrt(($x1 - $x0) * ($z1 - $z0))}]]
set H0 [expr {$z1 - $z0}]
set V0 [expr {($x1 - $x0) * ($y1 - $y0) * $H0}]
set fraction0 [expr {[tcl::mathop::+ {*}[lmap rr [element array radius] {expr {4.0 / 3 * acos(-1) * $rr ** 3}}]] / $V0}]

# The shear: the top platen down at the strain rate; the four lateral walls under servo. The
# default rate gives an inertial number I = rate d sqrt(rho / sigma3) of 1e-3 (quasi-static).
set rate [expr {$opt(-rate) ne {} ? $opt(-rate) : 1e-3 / (2 * $r * sqrt($rho / $sigma3))}]
set inertial [expr {$rate * 2 * $r * sqrt($rho / $sigma3)}]
set v [expr {$rate * $H0}]
wall set top -velocity [list 0 0 [expr {-$v}]]
set lateralSpeed [expr {20 * $v}]
# A row every 1e-3 of axial strain (at least one chunk of 100 steps).
set rowSteps [expr {max(100, int(1e-3 / ($rate * $dt)))}]

set fh [open $opt(-csv) w]
puts $fh "axial_strain,volumetric_strain,sigma1_Pa,sigma3_xlo_Pa,sigma3_xhi_Pa,sigma3_ylo_Pa,sigma3_yhi_Pa,q_Pa"
set curve {}
set worstConf 0
set peakQ 0
set peakStrain 0
set peakPhi 0
set start [clock milliseconds]
set shearSteps 0
while {1} {
    triaxial::servoAll $lateral $lateralSpeed
    sim run -steps $rowSteps -quiet -progress 0
    incr shearSteps $rowSteps
    set b [triaxial::box]
    dict with b {}
    set H [expr {$z1 - $z0}]
    set axial [expr {1 - $H / $H0}]
    set volumetric [expr {1 - ($x1 - $x0) * ($y1 - $y0) * $H / $V0}]
    set s1 [triaxial::wallStress top $b]
    set s3s [lmap w $lateral {triaxial::wallStress $w $b}]
    set s3 [expr {[tcl::mathop::+ {*}$s3s] / 4}]
    set q [expr {$s1 - $s3}]
    puts $fh [join [list $axial $volumetric $s1 {*}$s3s $q] ,]
    lappend curve [list $axial $volumetric $q $s1 {*}$s3s]
    foreach s $s3s {set worstConf [expr {max($worstConf, abs($s / $sigma3 - 1))}]}
    if {$q > $peakQ} {
        set peakQ $q
        set peakStrain $axial
        set peakPhi [expr {asin($q / ($s1 + $s3)) * 180 / acos(-1)}]
    }
    if {$axial >= $strainEnd} break
}
close $fh
set seconds [expr {([clock milliseconds] - $start) / 1000.0}]
lassign [lindex $curve end] endStrain endVol endQ
# The largest contraction (the volumetric strain's maximum) and where it is.
set maxContraction 0
set contractionStrain 0
foreach row $curve {
    lassign $row e ev
    if {$ev > $maxContraction} {
        set maxContraction $ev
        set contractionStrain $e
    }
}
# The residual strength: the mean q over the last quarter of the rows (one reading of a few
# hundred grains fluctuates by several percent).
set tail [lrange $curve [expr {3 * [llength $curve] / 4}] end]
set residualQ [expr {[tcl::mathop::+ {*}[lmap row $tail {lindex $row 2}]] / [llength $tail]}]
puts [format "triaxial (%s): %d grains, solid fraction %.4f after consolidation (%d steps%s); shear at %.3g/s (inertial number %.1e), %d steps of %.3g s in %.1f s: peak q %.4g kPa at axial strain %.4f, phi %.2f deg; at the end q %.4g kPa (%.4g kPa over the last quarter), volumetric strain %.4f (largest contraction %.4f at %.4f); confinement within %.2f %% of sigma3 on every lateral wall; table in %s" \
    $opt(-sample) $N $fraction0 $consolSteps [expr {$consolidated ? "" : ", NOT at rest"}] $rate $inertial $shearSteps $dt $seconds \
    [expr {$peakQ / 1e3}] $peakStrain $peakPhi [expr {$endQ / 1e3}] [expr {$residualQ / 1e3}] $endVol $maxContraction \
    $contractionStrain [expr {100 * $worstConf}] $opt(-csv)]
dict create sample $opt(-sample) elements $N consolidated $consolidated fraction $fraction0 rate $rate inertial $inertial \
    peakq $peakQ peakstrain $peakStrain phi $peakPhi endq $endQ residualq $residualQ endvol $endVol \
    maxcontraction $maxContraction confinement $worstConf curve $curve sigma3 $sigma3
