# Simple shear of frictional spheres in a fully periodic cell with Lees-Edwards boundaries: the
# effective friction mu = tau / p against the inertial number I = gdot d / sqrt(p / rho) of
# dense granular flow (GDR MiDi, Eur. Phys. J. E 14 (2004) 341; da Cruz et al., Phys. Rev. E 72
# (2005) 021309). The cell is filled at a low solid fraction, the grains are grown to the target
# solid fraction phi while the cell shears (volume fixed), then the stress is averaged over a
# strain window once the flow is steady. At a fixed solid fraction of stiff grains, I is set
# by phi alone (the rate only scales the stresses by gdot^2), so a sweep of phi spans I.
#
#   build/demlab examples/shear_cell.tcl ?-phi 0.58? ?-count 1000? ?-rate 10? ?-friction 0.5?
#                                        ?-strain 6? ?-young 1e8? ?-seed 1? ?-short 1?
#
# Grains: diameters uniform in [0.8, 1.2] d (d = 2 mm: no crystallisation), glass density,
# restitution 0.6, Hertz-Mindlin. The stress is the contacts' (Love-Weber, `query stress -part
# contacts` over the whole cell: the kinetic part is a few per cent of it in dense flow and
# would count the mean shear flow); tau is the symmetric shear component. Prints one line and
# returns a dict: phi, I, mu, p (Pa), tau (Pa), gdot, d, strain, samples, kappa (p / E*: the
# grains are rigid enough when it is small), and residual (the energy ledger's).

array set opt {-phi 0.58 -count 1000 -rate 10.0 -friction 0.5 -strain 6.0 -young 1e8 -seed 1
    -short 0}
foreach {k v} $argv {
    if {![info exists opt($k)]} {error "shear_cell.tcl: unknown option \"$k\""}
    set opt($k) $v
}
if {$opt(-short)} {
    array set opt {-count 250 -strain 3.0}
}
set d 0.002
set n $opt(-count)
set rate $opt(-rate)
# The mean sphere volume of diameters uniform in [0.8, 1.2] d: pi/6 <D^3> = pi/6 d^3 (1 + 0.04).
set meanVolume [expr {acos(-1) / 6 * $d ** 3 * 1.04}]
set L [expr {($n * $meanVolume / $opt(-phi)) ** (1.0 / 3)}]

sim new
material add glass -density 2500 -young $opt(-young) -poisson 0.25 -restitution 0.6 \
    -friction $opt(-friction)
# Placed small (a third of the final solid fraction), then grown.
set shrink [expr {(1.0 / 3) ** (1.0 / 3)}]
pack random -region [list box {0 0 0} [list $L $L $L]] -count $n -seed $opt(-seed) \
    -radius [list uniform [expr {0.4 * $d * $shrink}] [expr {0.6 * $d * $shrink}]]
periodic set -axes {x y z} -lo {0 0 0} -hi [list $L $L $L] -shear $rate
# The mean shear flow from the start, so the cell need not wait for momentum to diffuse.
foreach e [element list] {
    set y [lindex [element get $e -position] 1]
    element set $e -velocity [list [expr {$rate * ($y - $L / 2)}] 0 0]
}

# Growth: 1% in radius per tenth of a unit of strain, to the target solid fraction.
set growSteps [expr {int(ceil(log(1.0 / $shrink) / log(1.01)))}]
set factor [expr {(1.0 / $shrink) ** (1.0 / $growSteps)}]
for {set k 0} {$k < $growSteps} {incr k} {
    element resize -factor $factor
    sim run -time [expr {0.1 / $rate}] -quiet
}
# Steady flow: one unit of strain, then the sampled window.
sim run -time [expr {1.0 / $rate}] -quiet
set samples [expr {int($opt(-strain) * 10)}]
set sumP 0.0; set sumT 0.0
set volume [expr {$L ** 3}]
for {set k 0} {$k < $samples} {incr k} {
    sim run -time [expr {0.1 / $rate}] -quiet
    set s [dict get [query stress -volume $volume -part contacts] tensor]
    set sumP [expr {$sumP + ([lindex $s 0] + [lindex $s 4] + [lindex $s 8]) / 3}]
    # Compression positive: the cell's shear stress opposing the shear is -sigma_xy.
    set sumT [expr {$sumT - ([lindex $s 1] + [lindex $s 3]) / 2}]
}
set p [expr {$sumP / $samples}]
set tau [expr {$sumT / $samples}]
set I [expr {$rate * $d / sqrt($p / 2500.0)}]
set estar [expr {$opt(-young) / (2 * (1 - 0.25 ** 2))}]
set result [dict create phi $opt(-phi) I $I mu [expr {$tau / $p}] p $p tau $tau gdot $rate \
    d $d strain $opt(-strain) samples $samples kappa [expr {$p / $estar}] \
    residual [query energy -residual]]
puts [format "phi %.3f  I %.4g  mu %.4f  p %.4g Pa  tau %.4g Pa  p/E* %.2g  residual %.2g" \
    $opt(-phi) $I [dict get $result mu] $p $tau [dict get $result kappa] \
    [dict get $result residual]]
set result
