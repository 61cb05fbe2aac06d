# The bonded rock the laboratory examples share (ucs.tcl, brazil.tcl, borehole.tcl), after
# Potyondy and Cundall's parallel-bonded model (Int. J. Rock Mech. Min. Sci. 41, 2004) at a
# smaller scale: discs (2D) or spheres (3D) of radii uniform in [0.3, 0.5] mm (their ratio
# 1.66), linear contacts of modulus E_c = 30 GPa, parallel bonds of modulus E_c = kn (Ri +
# Rj) = 30 GPa at the mean radius, kn / ks = 2.5, strengths 50 MPa +- 20 %, made by
# demlab::sample at a locked-in stress of 0.4 % of the bond strength.
#
#   source examples/rock.tcl; rock::scene 2; rock::sample {box {0 0} {0.01 0.02}}

namespace eval rock {
    variable rmin 0.0003
    variable rmax 0.0005
    variable modulus 3e10      ;# E_c, Pa
    variable strength 5e7      ;# bond tensile and shear strength, Pa
}

# Starts a new scene of dimension d with the rock's material and rigid platens ("plate"), the
# contacts' modulus E_c times cscale.
# Returns nothing.
proc rock::scene {d {cscale 1}} {
    sim new -dim $d
    # Restitution 0.2: the contacts' damping settles the genesis and takes the platens' noise.
    material add rock -density 2650 -young 3e10 -poisson 0.25 -restitution 0.2 -friction 0.5
    material add plate -rigid 1 -density 7800 -poisson 0.3 -restitution 0.2 -friction 0.5
    # Linear contacts as stiff as the bonds (Potyondy and Cundall's contact modulus E_c):
    # kn = E* R* = 2 E_c (per unit thickness) in 2D, 4 E_c R in 3D, at the mean radius. (2D
    # forces are per unit thickness, so a 2D Hertz contact of the mineral's modulus would be far
    # softer than the bonds.) The platens alike (R* = R on a wall: twice as stiff).
    variable rmin
    variable rmax
    variable modulus
    set rstar [expr {($rmin + $rmax) / 4}]
    set young [expr {$cscale * ($d == 2 ? 2 * $modulus / $rstar : 8 * $modulus)}]
    law default linear
    law coefficients rock rock -young $young
    law coefficients rock plate -young $young
}

# Defines the parallel bond model "cement": modulus E_c times kscale, strengths times sscale.
# Returns nothing.
proc rock::cement {{kscale 1} {sscale 1}} {
    variable rmin
    variable rmax
    variable modulus
    variable strength
    set kn [expr {$kscale * $modulus / ($rmin + $rmax)}]
    set sigma [expr {$sscale * $strength}]
    bond model parallel cement -kn $kn -ks [expr {$kn / 2.5}] -tensile $sigma -shear $sigma \
        -scatter 0.2 -seed 3
}

# Makes the bonded sample filling region with demlab::sample (the elements tagged sample).
# Returns demlab::sample's dict.
proc rock::sample {region args} {
    variable rmin
    variable rmax
    demlab::sample -region $region -radius [list uniform $rmin $rmax] -model cement \
        -material rock -steps 800 -iterations 2000 {*}$args
}

# Returns the mean coordinate k of the elements carrying tag.
proc rock::meanOf {tag k} {
    set sum 0.0
    set n 0
    foreach p [element array position -tag $tag] {
        set sum [expr {$sum + [lindex $p $k]}]
        incr n
    }
    expr {$sum / $n}
}

# Returns {lo hi}: the extent along axis k of the elements carrying tag (their surfaces).
proc rock::extent {tag k} {
    set lo Inf
    set hi -Inf
    foreach p [element array position -tag $tag] r [element array radius -tag $tag] {
        set x [lindex $p $k]
        set lo [expr {min($lo, $x - $r)}]
        set hi [expr {max($hi, $x + $r)}]
    }
    list $lo $hi
}

# Tags the elements of tag whose centre lies within width of the sample's low (tag lo$k) and
# high (hi$k) faces along axis k. Returns nothing.
proc rock::tagFaces {tag k width} {
    lassign [extent $tag $k] lo hi
    foreach id [element list -tag $tag] p [element array position -tag $tag] r [element array radius -tag $tag] {
        set x [lindex $p $k]
        if {$x - $r < $lo + $width} {element tag lo$k $id}
        if {$x + $r > $hi - $width} {element tag hi$k $id}
    }
}

# Returns {tension shear} counts of the breaks so far.
proc rock::cracks {} {
    set c [bond count]
    list [dict get $c tension] [dict get $c shear]
}

# Writes the bonded sample and its loading for another DEM code to rebuild (scripts/peer-bond):
# prefix.elements.csv (dump csv: id radius mass x y z), prefix.bonds.csv (a,b,tensile,shear,
# restlength,gap: every intact bond with its own drawn strengths, Pa, and the surface gap it
# was made at, m) and prefix.meta (key value lines; the lists are Tcl lists of element ids). The
# extra pairs are key value arguments written as they are. Returns nothing.
proc rock::export {prefix args} {
    dump csv $prefix.elements.csv -fields {id radius mass x y z}
    set fh [open $prefix.bonds.csv w]
    puts $fh a,b,tensile,shear,restlength,gap
    foreach b [bond list] {
        if {![dict get $b intact]} continue
        set q [bond query [dict get $b id]]
        set gap [expr {[dict get $q restlength] - [element get [dict get $b a] -radius] \
            - [element get [dict get $b b] -radius]}]
        puts $fh [join [list [dict get $b a] [dict get $b b] [dict get $q tensile] \
            [dict get $q shear] [dict get $q restlength] $gap] ,]
    }
    close $fh
    set fh [open $prefix.meta w]
    set bond [lindex [bond models] 0]
    foreach {k v} [dict get $bond values] {puts $fh "bond_$k $v"}
    foreach pair {{rock rock} {rock plate}} {
        set c [law coefficients {*}$pair]
        foreach k {young friction restitution} {puts $fh "[join $pair _]_$k [dict get $c $k]"}
    }
    foreach k {density poisson} {puts $fh "rock_$k [material get rock -$k]"}
    puts $fh "dt [sim timestep]"
    foreach {k v} $args {puts $fh "$k $v"}
    close $fh
}

# Returns the CPU time (user and system) this process has used, s, or "" where Linux's
# /proc/self/stat is not there. On a machine shared with other jobs it is steadier than the wall
# time, which counts the time others held the core.
proc rock::cpuSeconds {} {
    variable clockTicks
    if {![file readable /proc/self/stat]} {return {}}
    if {![info exists clockTicks]} {
        if {[catch {exec getconf CLK_TCK} clockTicks]} {set clockTicks 100}
    }
    set fh [open /proc/self/stat]
    set stat [read $fh]
    close $fh
    # The fields after the command's name, which is in parentheses: the state is the third
    # field, utime and stime (clock ticks) the 14th and 15th.
    set fields [string range $stat [string last ) $stat]+2 end]
    expr {double([lindex $fields 11] + [lindex $fields 12]) / $clockTicks}
}

# Reads an example's arguments into the array named arrayName, which holds the defaults: -short
# alone sets opt(-short) to 1, any other known -option takes the next word, anything else is
# the CSV file (opt(-csv)). Returns nothing.
proc rock::parseArgs {arrayName words} {
    upvar 1 $arrayName opt
    for {set k 0} {$k < [llength $words]} {incr k} {
        set a [lindex $words $k]
        if {$a eq "-short"} {
            set opt(-short) 1
        } elseif {[info exists opt($a)]} {
            set opt($a) [lindex $words [incr k]]
        } else {
            set opt(-csv) $a
        }
    }
}
