# The Janssen effect in a tall silo (3D): frictional spheres poured (packed at random in the
# silo, then let fall and settle under gravity) into a vertical cylinder (wall add drum) closed by
# a floor. The friction of the wall carries part of the weight, so the pressure on the wall stops
# growing with depth z below the surface. Janssen's slice balance, with a constant ratio K of
# the horizontal to the vertical stress and the wall friction mu_w fully mobilised, gives
#
#   sigma_v(z) = (rho_b g D / (4 mu_w K)) (1 - exp(-z / lambda)),  lambda = D / (4 mu_w K),
#   sigma_w(z) = K sigma_v(z),  saturating at rho_b g D / (4 mu_w).
#
# The script bins the normal forces of the grains' contacts with the cylinder (query contacts)
# by height, each bin over its wall area (pi D h), and takes each slab's mean vertical and
# horizontal stresses over the cross-section (query stress). Depth is measured from the surface
# of a bed of the bulk density rho_b measured in the bed holding all the mass. mu_w and K are
# separated thus: the vertical stress, whose curve starts hydrostatic, fits lambda alone, so
# mu_w K; the wall stress's asymptote A = rho_b g D / (4 mu_w) gives mu_w; the wall's contacts
# give mu_w directly (their vertical friction over their normal force, summed), and K is mu_w K
# over it, or directly the wall over the vertical stress. It also checks that the floor and the
# wall carry the weight and compares the floor's stress with Janssen's sigma_v at the bed's
# depth. The profile goes to a CSV table; the numbers are printed and returned as a dict.
#
#   build/demlab examples/janssen.tcl ?file.csv? ?-short? ?-seed n? ?-diameter D/d?
#                                     ?-height H/D? ?-wallfriction mu_w?
#
# -short: a silo 6 grain diameters wide (about 800 grains; the test suite's form); the full
# form 12 wide (about 6000). -height: the bed's height in silo diameters (default 4); the
# grains' own friction is 0.5, the wall's -wallfriction (default 0.3).

array set opt {-short 0 -seed 1 -diameter {} -height 4 -wallfriction 0.3 -csv janssen.csv}
set args $argv
while {[llength $args]} {
    set args [lassign $args a]
    switch -- $a {
        -short {set opt(-short) 1}
        -seed - -diameter - -height - -wallfriction {
            if {![llength $args]} {error "janssen.tcl: $a needs a value" {} {DEMLAB ARGS}}
            set args [lassign $args opt($a)]
        }
        default {
            if {[string match -* $a]} {
                error "janssen.tcl: unknown option \"$a\"" {} {DEMLAB OPTION}
            }
            set opt(-csv) $a
        }
    }
}
if {!([string is wideinteger -strict $opt(-seed)] && $opt(-seed) >= 0)} {
    error "janssen.tcl: bad seed \"$opt(-seed)\": must be a non-negative integer" {} {DEMLAB VALUE SEED}
}
foreach {o lo} {-diameter 4 -height 1 -wallfriction 0} {
    if {$opt($o) ne {} && !([string is double -strict $opt($o)] && $opt($o) > $lo && $opt($o) < 100)} {
        error "janssen.tcl: bad [string range $o 1 end] \"$opt($o)\": must be a number above $lo and below 100" \
            {} [list DEMLAB VALUE [string toupper [string range $o 1 end]]]
    }
}

set r 0.001                                ;# mean radius, m (uniform 0.8 r .. 1.2 r)
set rho 2500.0                             ;# the grains' density, kg/m^3
set g 9.81
set muGrain 0.5
set muWall $opt(-wallfriction)
set Dd [expr {$opt(-diameter) ne {} ? $opt(-diameter) : ($opt(-short) ? 6 : 12)}]
set D [expr {$Dd * 2 * $r}]                ;# the silo's diameter, m
set R [expr {$D / 2}]
set Hbed [expr {$opt(-height) * $D}]       ;# the bed's height aimed at, m

sim new -dim 3
material add grain -density $rho -young 2e6 -poisson 0.3 -restitution 0.3 -friction $muGrain
material add steel -density 7800 -young 2e6 -poisson 0.3 -restitution 0.3 -friction $muGrain
law default hertz
law coefficients grain steel -friction $muWall
behavior add gravity -g [list 0 0 [expr {-$g}]]
# The automatic step (0.2 of the Rayleigh step, at most half what the contacts' overlaps
# allow as the bed settles and loads them: doc/design.md, "The time step follows the contacts").

# The grains for a bed of height Hbed at a solid fraction of about 0.6, placed at 0.25 in a
# cylinder that much taller (so they fall at most 60 % of the height as they settle).
set vGrain [expr {4.0 / 3 * acos(-1) * $r ** 3 * 1.04}]   ;# <r^3> of uniform 0.8..1.2 is 1.04 r^3
set area [expr {acos(-1) * $R * $R}]
set N [expr {int(0.6 * $area * $Hbed / $vGrain)}]
set Hpack [expr {$N * $vGrain / (0.25 * $area)}]
set silo [wall add drum -radius $R -axis {0 0 1} -halflength [expr {$Hpack / 2 + $D}] \
    -point [list 0 0 [expr {$Hpack / 2}]] -material steel -name silo]
set floor [wall add plane -normal {0 0 1} -point {0 0 0} -material steel -name floor]
pack random -region [list cylinder [list 0 0 [expr {$Hpack / 2}]] {0 0 1} $R [expr {$Hpack / 2}]] \
    -radius [list uniform [expr {0.8 * $r}] [expr {1.2 * $r}]] -count $N -seed $opt(-seed) \
    -material grain -tags bed -tries 10000

# Settles until the kinetic energy is 1e-5 of the bed's weight times a grain radius (the grains'
# mean speed a few 1e-4 m/s), or for at most 200000 steps.
set mass [tcl::mathop::+ {*}[lmap rr [element array radius] {expr {4.0 / 3 * acos(-1) * $rho * $rr ** 3}}]]
set settled [demlab::settle -energy [expr {1e-5 * $mass * $g * $r}] -chunk 2000 -maxsteps 200000]
# Janssen takes the wall friction fully mobilised, the bed sliding down along the wall. A poured
# bed has not slid (its grains came to rest against the wall at any friction below the limit);
# lowering the floor slowly by a fifth of a grain diameter makes it slide (as the piston under
# the silo of Vanel et al., Phys. Rev. Lett. 84, 1439, 2000), mobilising the wall friction as
# far as its contacts do (measured below), then it settles again.
set drop [expr {0.4 * $r}]
set speed 0.005
wall set floor -velocity [list 0 0 [expr {-$speed}]]
sim run -time [expr {$drop / $speed}] -quiet -progress 0
wall set floor
set settled2 [demlab::settle -energy [expr {1e-5 * $mass * $g * $r}] -chunk 2000 -maxsteps 200000]
dict set settled steps [expr {[dict get $settled steps] + [dict get $settled2 steps] + int($drop / $speed / [sim timestep])}]
dict set settled settled [dict get $settled2 settled]
set base [lindex [wall get floor -point] 2]

# The bulk density: the grains whose centre lies in the middle half of the bed over its volume.
set zs [lmap p [element array position] {expr {[lindex $p 2] - $base}}]
set top [tcl::mathfunc::max {*}$zs]
set lo [expr {0.25 * $top}]
set hi [expr {0.75 * $top}]
set slabMass 0.0
foreach zz $zs rr [element array radius] {
    if {$zz >= $lo && $zz < $hi} {set slabMass [expr {$slabMass + 4.0 / 3 * acos(-1) * $rho * $rr ** 3}]}
}
set rhoB [expr {$slabMass / ($area * ($hi - $lo))}]
# The free surface (its height above the floor): where a bed of that bulk density holding all
# the mass would end.
set surface [expr {$mass / ($rhoB * $area)}]

# The wall's contacts, binned by height: normal force (the grain pushing outwards) and the
# tangential force's magnitude.
set binH [expr {4 * $r}]
set nBins [expr {int(ceil($surface / $binH))}]
set fn [lrepeat $nBins 0.0]
set sumN 0.0
set sumT 0.0
set sumUp 0.0
set full 0
set wallContacts 0
foreach c [query contacts] {
    if {[dict get $c wall] ne $silo} continue
    lassign [dict get $c force] fx fy fz
    lassign [dict get $c normal] nx ny nz
    set n [expr {$fx * $nx + $fy * $ny + $fz * $nz}]
    set t [expr {sqrt(max(0.0, $fx * $fx + $fy * $fy + $fz * $fz - $n * $n))}]
    set k [expr {int(([lindex [dict get $c point] 2] - $base) / $binH)}]
    if {$k < 0 || $k >= $nBins} continue
    lset fn $k [expr {[lindex $fn $k] + $n}]
    set sumN [expr {$sumN + $n}]
    set sumT [expr {$sumT + $t}]
    set sumUp [expr {$sumUp - $fz}]
    if {$t >= 0.99 * $muWall * $n} {incr full}
    incr wallContacts
}
set mobilised [expr {$sumT / $sumN}]
# The vertical friction over the normal force, summed over the wall: the mu_w of Janssen's
# balance (the wall holds sumUp of the weight; the floor the rest).
set muVertical [expr {$sumUp / $sumN}]
set wallShare [expr {$sumUp / ($mass * $g)}]
set floorStress [expr {-[lindex [wall get $floor -force] 2] / $area}]
set floorShare [expr {$floorStress * $area / ($mass * $g)}]

# The profile, depth below the surface at each bin's middle: the wall's normal stress, and the
# mean vertical and horizontal stresses over the silo's cross-section (Love-Weber averages of
# the slab, query stress over a box holding it, divided by the slab's volume in the cylinder).
# The fits leave out the bin at the floor (its grains also lean on the floor) and the bins
# within a grain diameter of the surface.
set fh [open $opt(-csv) w]
puts $fh "depth_m,height_m,wall_stress_Pa,vertical_stress_Pa,horizontal_stress_Pa,hydrostatic_Pa"
set profile {}
for {set k 0} {$k < $nBins} {incr k} {
    set zmid [expr {($k + 0.5) * $binH}]
    set depth [expr {$surface - $zmid}]
    set s [expr {[lindex $fn $k] / (acos(-1) * $D * $binH)}]
    set slab [list box [list [expr {-2 * $R}] [expr {-2 * $R}] [expr {$base + $k * $binH}]] \
        [list [expr {2 * $R}] [expr {2 * $R}] [expr {$base + ($k + 1) * $binH}]]]
    set tensor [dict get [query stress -region $slab -volume [expr {$area * $binH}] -part static] tensor]
    set sv [lindex $tensor 8]
    set sh [expr {([lindex $tensor 0] + [lindex $tensor 4]) / 2}]
    puts $fh [join [list $depth $zmid $s $sv $sh [expr {$rhoB * $g * $depth}]] ,]
    lappend profile [list $depth $s $sv $sh]
}
close $fh
set wallPts {}
set verticalPts {}
foreach row [lrange $profile 1 end] {
    lassign $row depth s sv
    if {$depth > 2 * $r} {
        lappend wallPts $depth $s
        lappend verticalPts $depth $sv
    }
}

# Least squares of s = A (1 - exp(-z / lambda)) over the pairs {z s} of pts: with slope given,
# A = slope lambda (the curve starts at that slope), else A in closed form for each lambda;
# lambda by a golden-section search of the residual over [D / 20, 20 D] on a logarithmic scale.
# Returns {A lambda}.
proc janssenFit {pts D {slope {}}} {
    set best {}
    set residual {{pts lambda slope} {
        if {$slope ne {}} {
            set A [expr {$slope * $lambda}]
        } else {
            set su 0.0
            set uu 0.0
            foreach {z s} $pts {
                set u [expr {1 - exp(-$z / $lambda)}]
                set su [expr {$su + $s * $u}]
                set uu [expr {$uu + $u * $u}]
            }
            set A [expr {$su / $uu}]
        }
        set e 0.0
        foreach {z s} $pts {set e [expr {$e + ($s - $A * (1 - exp(-$z / $lambda))) ** 2}]}
        list $e $A
    }}
    set a [expr {log($D / 20)}]
    set b [expr {log($D * 20)}]
    set phi [expr {(sqrt(5) - 1) / 2}]
    for {set it 0} {$it < 80} {incr it} {
        set c [expr {$b - $phi * ($b - $a)}]
        set d [expr {$a + $phi * ($b - $a)}]
        set ec [lindex [apply $residual $pts [expr {exp($c)}] $slope] 0]
        set ed [lindex [apply $residual $pts [expr {exp($d)}] $slope] 0]
        if {$ec < $ed} {set b $d} else {set a $c}
    }
    set lambda [expr {exp(($a + $b) / 2)}]
    list [lindex [apply $residual $pts $lambda $slope] 1] $lambda
}
# The vertical stress: Janssen's curve starts hydrostatic (slope rho_b g), so lambda alone
# fits it, and gives the product mu_w K = D / (4 lambda).
lassign [janssenFit $verticalPts $D [expr {$rhoB * $g}]] B lambda
set muK [expr {$D / (4 * $lambda)}]
# The wall stress: its asymptote A = rho_b g D / (4 mu_w) gives mu_w by itself.
lassign [janssenFit $wallPts $D] A lambdaWall
set muFit [expr {$rhoB * $g * $D / (4 * $A)}]
# K from the product and the wall friction the wall measured (vertical friction over normal
# force), and directly: the wall stress over the vertical stress, summed over the fitted bins.
set K [expr {$muK / $muVertical}]
set sumW 0.0
set sumV 0.0
foreach {z s} $wallPts {z2 sv} $verticalPts {
    set sumW [expr {$sumW + $s}]
    set sumV [expr {$sumV + $sv}]
}
set Kdirect [expr {$sumW / $sumV}]
# Janssen's vertical stress at the floor, from the fit, against the floor's own.
set floorJanssen [expr {$B * (1 - exp(-$surface / $lambda))}]
# The deepest bins of the fit (the lowest quarter; the first of the list) against the
# asymptote and the hydrostatic rho_b g z.
set deep [lrange $wallPts 0 [expr {2 * max(1, [llength $wallPts] / 8) - 1}]]
set deepStress 0.0
set deepDepth 0.0
foreach {z s} $deep {
    set deepStress [expr {$deepStress + $s}]
    set deepDepth [expr {$deepDepth + $z}]
}
set deepStress [expr {$deepStress / ([llength $deep] / 2)}]
set deepDepth [expr {$deepDepth / ([llength $deep] / 2)}]

puts [format "janssen: %d grains in a silo %g grains wide (D = %.3g m), bed %.3g m deep (%.2f D), bulk density %.4g kg/m^3 (fraction %.3f), %d steps; vertical stress fit lambda = %.4g m (%.2f D): mu_w K = %.4f; wall stress fit %.4g Pa (1 - exp(-z / %.4g m)): mu_w from its asymptote %.3f; on the wall: vertical friction / normal force %.3f (set %.3g; |tangential| / normal %.3f, %.0f %% of %d contacts at the limit); K = mu_w K / mu_w = %.3f, sigma_w / sigma_v directly %.3f; the wall carries %.3f of the weight, the floor %.3f; deepest bins %.4g Pa at %.3g m depth (asymptote %.4g Pa, hydrostatic %.4g Pa); floor %.4g Pa (Janssen %.4g Pa, hydrostatic %.4g Pa); table in %s" \
    $N $Dd $D $surface [expr {$surface / $D}] $rhoB [expr {$rhoB / $rho}] [dict get $settled steps] \
    $lambda [expr {$lambda / $D}] $muK $A $lambdaWall $muFit $muVertical $muWall $mobilised \
    [expr {100.0 * $full / max(1, $wallContacts)}] $wallContacts $K $Kdirect $wallShare $floorShare \
    $deepStress $deepDepth $A [expr {$rhoB * $g * $deepDepth}] $floorStress $floorJanssen \
    [expr {$rhoB * $g * $surface}] $opt(-csv)]
dict create elements $N diameter $D depth $surface rhob $rhoB lambda $lambda muK $muK \
    asymptote $A lambdawall $lambdaWall muasymptote $muFit muvertical $muVertical muset $muWall \
    mobilised $mobilised fullshare [expr {double($full) / max(1, $wallContacts)}] K $K \
    Kdirect $Kdirect wallshare $wallShare floorshare $floorShare deepstress $deepStress \
    deepdepth $deepDepth floor $floorStress floorjanssen $floorJanssen profile $profile \
    steps [dict get $settled steps] settled [dict get $settled settled]
