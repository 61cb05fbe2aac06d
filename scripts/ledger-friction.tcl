# The energy ledger's residual of a settling bed against the time step, by what the contacts
# hold: 200 soft Hertz grains (E = 5 MPa, 0.8-1.2 mm) dropped into a 12 mm box for 0.08 s at
# 0.2, 0.1 and 0.05 of the critical step (no accuracy target), with friction 0 or 0.5,
# restitution 1 or 0.5, rotation on or off. Prints one CSV row a case:
# law,rotation,friction,restitution,residual_0.2,residual_0.1,residual_0.05.
#   build/demlab scripts/ledger-friction.tcl ?hertz|linear?
set law [expr {[llength $argv] ? [lindex $argv 0] : "hertz"}]
# (scripts/ledger-normal.tcl sources this file for settle, with touch.)
proc settle {law rotation fraction mu e {touch off}} {
    sim new
    material add glass -density 2500 -young 5e6 -poisson 0.3 -restitution $e -friction $mu
    law default $law
    module rotation $rotation
    module touch $touch
    foreach {n p} {{1 0 0} {0 0 0} {-1 0 0} {0.012 0 0} {0 1 0} {0 0 0} {0 -1 0} {0 0.012 0} {0 0 1} {0 0 0}} {
        wall add plane -normal $n -point $p
    }
    behavior add gravity
    sim timestep auto -fraction $fraction -stepspercontact 0
    pack random -region {box {0 0 0.002} {0.012 0.012 0.03}} -radius {uniform 0.0008 0.0012} -count 200 -seed 2
    sim run -time 0.08 -quiet
    format %.3g [query energy -residual]
}
if {[info exists ::ledgerFrictionProcsOnly]} return
puts "law,rotation,friction,restitution,residual_0.2,residual_0.1,residual_0.05"
foreach {rotation mu e} {on 0 1  on 0.5 1  off 0.5 1  on 0 0.5  on 0.5 0.5} {
    set row [list $law $rotation $mu $e]
    foreach fraction {0.2 0.1 0.05} {lappend row [settle $law $rotation $fraction $mu $e]}
    puts [join $row ,]
}
