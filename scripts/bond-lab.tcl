# The bonded-sample laboratory's studies (run by scripts/bond-figures): the examples ucs.tcl,
# brazil.tcl and borehole.tcl in their full forms, on one thread, their CSV tables and frames
# written into OUTDIR and their figures as Markdown tables into OUTDIR/tables.md:
#   - unconfined compression at 4/s and at 2/s (quasi-static: the rate halved), and in 3D;
#   - micro to macro: the bonds' stiffness and strength times 0.5, 1 and 2, at 4/s;
#   - the Brazilian test; the borehole breakout.
#
#   build/demlab scripts/bond-lab.tcl OUTDIR

set out [file normalize [lindex $argv 0]]
set examples [file join [file dirname [file dirname [file normalize [info script]]]] examples]
file mkdir $out
cd $out

# Runs examples/NAME.tcl with the arguments args; returns the dict it returns.
proc example {name args} {
    global examples
    set ::argv $args
    uplevel #0 [list source [file join $examples $name.tcl]]
}

set md {}
# Appends a line to the tables.
proc line {text} {
    global md
    append md $text \n
}

set ucs [dict create]
foreach {key rate k s c} {r4 4 1 1 1 r2 2 1 1 1 k05 4 0.5 1 1 k2 4 2 1 1 s05 4 1 0.5 1 s2 4 1 2 1 e05 4 0.5 1 0.5 e15 4 1.5 1 1.5} {
    dict set ucs $key [example ucs ucs-$key.csv -rate $rate -kscale $k -sscale $s -cscale $c]
}
dict set ucs d3 [example ucs ucs-3d.csv -dim 3 -rate 4]
set base [dict get $ucs r4]
line "Sample (\`demlab::sample\`, examples/rock.tcl): [dict get $base elements] discs, [dict get $base bonds] bonds,\
    solid fraction [format %.3f [dict get $base fraction]]; the mean stress of the forces between its elements when bonded\
    [format %.3g [dict get $base stress]] Pa, and of its contacts alone after the walls went [format %.3g [dict get $base lockedin]] Pa\
    (the compression the bonds' tension balances: \`query stress -part contacts\`),\
    against the bond strength 50 MPa[expr {[dict get $base stress] == 0 && [dict get $base lockedin] == 0 ?\
    { (0: no contact overlaps; the relax left them below 1e-5 radii)} : {}}]."
line ""
line "| run | elements / bonds | strain rate (1/s) | peak (MPa) | strain at peak | E (GPa) | Poisson's ratio | cracks at peak | tension / shear at the end | steps | time per step (us) |"
line "|---|---|---|---|---|---|---|---|---|---|---|"
foreach {key label} {r4 {base} r2 {rate halved} k05 {bond kn, ks x 0.5} k2 {bond kn, ks x 2} e05 {bonds' and contacts' moduli x 0.5} e15 {bonds' and contacts' moduli x 1.5} s05 {bond strengths x 0.5} s2 {bond strengths x 2} d3 {3D, base}} {
    set r [dict get $ucs $key]
    line [format "| %s | %d / %d | %g | %.2f | %.5f | %.2f | %.3f | %d | %d / %d | %d | %.0f |" $label \
        [dict get $r elements] [dict get $r bonds] [dict get $r rate] \
        [expr {[dict get $r peak] / 1e6}] [dict get $r peakstrain] [expr {[dict get $r modulus] / 1e9}] \
        [dict get $r poisson] [dict get $r peakcracks] [dict get $r tension] [dict get $r shear] \
        [dict get $r steps] [expr {1e6 * [dict get $r seconds] / [dict get $r steps]}]]
}
set r2 [dict get $ucs r2]
line ""
line [format "Halving the strain rate changes the peak by %+.1f %%, the modulus by %+.1f %% and Poisson's ratio by %+.3f." \
    [expr {100 * ([dict get $r2 peak] / [dict get $base peak] - 1)}] \
    [expr {100 * ([dict get $r2 modulus] / [dict get $base modulus] - 1)}] \
    [expr {[dict get $r2 poisson] - [dict get $base poisson]}]]
line ""
line "Micro to macro (ratios to the base run; Potyondy and Cundall: the modulus follows the bond stiffness, the strength the bond strength):"
line ""
line "| bond change | E / E_base | peak / peak_base |"
line "|---|---|---|"
foreach {key label} {k05 {bond kn, ks x 0.5} k2 {bond kn, ks x 2} e05 {bonds' and contacts' moduli x 0.5} e15 {bonds' and contacts' moduli x 1.5} s05 {bond strengths x 0.5} s2 {bond strengths x 2}} {
    set r [dict get $ucs $key]
    line [format "| %s | %.3f | %.3f |" $label [expr {[dict get $r modulus] / [dict get $base modulus]}] \
        [expr {[dict get $r peak] / [dict get $base peak]}]]
}

set br [example brazil brazil.csv]
line ""
line [format "Brazilian test (examples/brazil.tcl): a disc of %d discs, %d bonds, D = %.2f mm; peak force %.2f kN/m, sigma_t = 2F/(pi D t) = %.2f MPa (t = 1 m: 2D forces are per unit thickness), UCS / sigma_t = %.2f; %d cracks at the peak, %d tension and %d shear at the end, %.0f %% of them within D/10 of the loaded diameter (%.0f %% of the disc's area is)." \
    [dict get $br elements] [dict get $br bonds] [expr {1e3 * [dict get $br diameter]}] \
    [expr {[dict get $br peakforce] / 1e3}] [expr {[dict get $br tensile] / 1e6}] \
    [expr {[dict get $base peak] / [dict get $br tensile]}] [dict get $br peakcracks] \
    [dict get $br tension] [dict get $br shear] [expr {100 * [dict get $br central]}] \
    [expr {100 * [dict get $br uniform]}]]

set bh [example borehole borehole.csv -frames [file join $out frames]]
line ""
line [format "Borehole breakout (examples/borehole.tcl, a 12 mm block, a hole of radius 1.8 mm, S1 = 60 MPa, S3 = 20 MPa): %d discs, %d bonds after drilling; the servo walls held %.1f MPa across x and %.1f MPa across y; %d bonds broke, %d of them within 2.5 hole radii, %.0f %% of those within 30 degrees of the y axis (a uniform spread: 33 %%). Broken bonds per 10-degree bin from the x axis: %s." \
    [dict get $bh elements] [dict get $bh bonds] [expr {[dict get $bh sx] / 1e6}] \
    [expr {[dict get $bh sy] / 1e6}] [dict get $bh broken] [dict get $bh near] \
    [expr {100 * [dict get $bh share]}] [join [dict get $bh bins] {, }]]

set fh [open [file join $out tables.md] w]
puts -nonewline $fh $md
close $fh
puts "bond-lab: tables in [file join $out tables.md]"
