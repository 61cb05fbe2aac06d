# What the energy ledger's residual is made of where grains collide with damping, at demlab's
# defaults (the synchronized integrator): one CSV row a case.
#  1. One 1 mm Hertz (or linear) grain, E = 5 MPa, e = 0.5 or 1, frictionless, launched at
#     0.5 m/s onto a floor, at 10, 20, 40 and 80 steps per contact (the automatic step's
#     accuracy target), the touch correction off and on: the residual after the rebound.
#  2. 200 such grains (0.8-1.2 mm) dropped into a 12 mm box for 0.08 s, at 0.2, 0.1, 0.05 and
#     0.025 of the critical step (no accuracy target), frictionless or mu = 0.5, e = 0.5 or 1,
#     touch off and on.
#  3. The stability suite's shaken bed (tests/tcl/stability.test, stability-6.3: 200 grains,
#     mu = 0.5, e = 0.5, settled 0.08 s, the floor shaken at 10 g and 50 Hz for 0.2 s) and the
#     README's settling bed (400 grains, 0.1 s), at the default step with 20, 30 and 40 steps
#     per contact.
#   build/demlab scripts/ledger-normal.tcl
proc drop {law e touch spc} {
    sim new
    material add glass -density 2500 -young 5e6 -poisson 0.3 -restitution $e -friction 0
    law default $law
    module touch $touch
    wall add plane -normal {0 0 1} -point {0 0 0}
    sim timestep auto -fraction 1 -stepspercontact $spc
    element add -radius 0.001 -position {0 0 0.00101} -velocity {0 0 -0.5}
    sim run -time 0.01 -quiet
    format %.3g [query energy -residual]
}
# settle {law rotation fraction mu e touch}: the settling bed of scripts/ledger-friction.tcl.
set ::ledgerFrictionProcsOnly 1
source [file join [file dirname [info script]] ledger-friction.tcl]
proc shaken {spc} {
    sim new
    material add glass -density 2500 -young 5e6 -poisson 0.3 -restitution 0.5 -friction 0.5
    law default hertz
    foreach {n p} {{1 0 0} {0 0 0} {-1 0 0} {0.012 0 0} {0 1 0} {0 0 0} {0 -1 0} {0 0.012 0}} {
        wall add plane -normal $n -point $p
    }
    behavior add gravity
    sim timestep auto -stepspercontact $spc
    wall add plane -name floor -normal {0 0 1} -point {0 0 0}
    pack random -region {box {0 0 0.002} {0.012 0.012 0.03}} -radius {uniform 0.0008 0.0012} -count 200 -seed 2
    sim run -time 0.08 -quiet
    set f 50.0
    wall set floor -amplitude [list 0 0 [expr {10 * 9.81 / (2 * acos(-1) * $f) ** 2}]] -frequency $f
    sim run -time 0.2 -quiet
    format %.3g [query energy -residual]
}
proc readmeBed {spc} {
    sim new -dim 3
    material add glass -density 2500 -young 5e6 -poisson 0.3 -restitution 0.5 -friction 0.5
    wall add plane -point {0 0 0} -normal {0 0 1}
    foreach {p n} {{0 0 0} {1 0 0}  {0.02 0 0} {-1 0 0}  {0 0 0} {0 1 0}  {0 0.02 0} {0 -1 0}} {
        wall add plane -point $p -normal $n
    }
    pack random -region {box {0 0 0} {0.02 0.02 0.03}} -radius {uniform 0.0008 0.001} -count 400 -seed 1
    behavior add gravity
    sim timestep auto -stepspercontact $spc
    set r [sim run -time 0.1 -quiet]
    format "%.3g (%d steps)" [dict get $r residual] [dict get $r steps]
}
puts "case,law,friction,restitution,touch,residual_1,residual_2,residual_3,residual_4"
foreach law {hertz linear} {
    foreach e {0.5 1} {
        foreach touch {off on} {
            set row [list drop(10/20/40/80_steps_per_contact) $law 0 $e $touch]
            foreach spc {10 20 40 80} {lappend row [drop $law $e $touch $spc]}
            puts [join $row ,]
        }
    }
}
foreach {mu e} {0 1  0 0.5  0.5 0.5} {
    foreach touch {off on} {
        set row [list settle(0.2/0.1/0.05/0.025_of_critical) hertz $mu $e $touch]
        foreach fraction {0.2 0.1 0.05 0.025} {lappend row [settle hertz on $fraction $mu $e $touch]}
        puts [join $row ,]
    }
}
foreach {name proc} {shaken(20/30/40_steps_per_contact) shaken readme(20/30/40_steps_per_contact) readmeBed} {
    set row [list $name hertz 0.5 0.5 off]
    foreach spc {20 30 40} {lappend row [$proc $spc]}
    puts [join $row ,]
}
