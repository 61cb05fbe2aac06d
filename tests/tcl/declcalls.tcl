# Calls built from the command declarations (help -declarations), shared by the bad-input
# table (badinput.test) and the command-sequence fuzzer (tests/fuzz/command_fuzz.tcl): a valid
# word for every parameter type, the bad words each type must refuse, and the absurd words it
# admits. Nothing here changes the scene; the words that name things of a scene live in the
# namespace valid and are set by whoever builds the scene.

namespace eval valid {
    # Words naming what the scene holds, by type label (the declaration's "label").
    variable byLabel [dict create \
        element first wall floor material glass tag grains {list of tags} grains \
        spin {0 0 1} region {box {-0.05 -0.05 0.4} {0.05 0.05 0.5}} \
        {size distribution} 0.002 law linear {kept scene} base model glue \
        {list of element pairs} {{first 1}} {list of parts} elements {list of fields} {id x} \
        quantity time quantities kinetic {list of quantities} {time kinetic} real|auto auto \
        file out.dat path out.dat folder outdir {path prefix} out/p file.png plot.png \
        WxH 32x24 {field or colour} speed colour white unit m command ::valid::tinyScene \
        script {expr 1.0} numbers|script 1.0 {{min max}, first or auto} auto \
        {{px py pz nx ny nz}} {0 0 0 0 0 1} {list of x y z rx ry rz} x {shape type} sphere \
        word sim {vector of expressions} {0 0 0} {spin of expressions} {0 0 0} \
        {series id} {first-of ::valid::firstId series} {dump id} {first-of ::valid::firstId dump} \
        {snapshot id} {first-of ::valid::firstId snapshot} \
        behavior {first-of ::valid::firstId behavior}]
    # Words for one command's parameter ("command param"), where the type alone does not say
    # which thing of the scene it names.
    variable byParam [dict create \
        {material get name} glass {material set name} glass {inlet get name} feed \
        {inlet remove name} feed {sink get name} drain {sink remove name} drain \
        {law coefficients a} glass {law coefficients b} steel {law pair a} glass \
        {law pair b} steel {sim keep name} other {module get option} name \
        {sim load file} base.ckpt {pack file file} base.data {bond file path} pairs.txt \
        {snapshot read file} base.png]
    # Options a command needs beyond what its declaration requires (the need depends on other
    # options: a sphere needs -radius, a material that is not rigid -young).
    variable extra [dict create {material add} {-young 5e6} {element add} {-radius 0.01} \
        {sink add} {-region {box {-1 -1 -1} {1 1 -0.5}}} {wall add drum} {-halflength 0.2}]
    # Returns the id of the first object `group list` lists (its entries are ids, or dicts
    # with an id).
    proc firstId {group} {
        set first [lindex [$group list] 0]
        expr {[llength $first] > 1 ? [dict get $first id] : $first}
    }
    # A scene for study convergence: one grain, one step long.
    proc tinyScene {} {
        sim new -dim 3
        material add glass -density 2500 -young 5e6 -poisson 0.3 -restitution 0.5 -friction 0.5
        element add -radius 0.01
    }
}

# Returns the commands that build a 3D scene with one of everything, as a list of calls: two
# materials, elements with a name and a tag, four kinds of wall, a bond, gravity and a load, an
# inlet, a sink, a dump and a series output (writing under dir), and a kept copy named base.
proc sceneSteps {dir} {
    list {sim new -dim 3} \
        {material add glass -density 2500 -young 5e6 -poisson 0.3 -restitution 0.5 -friction 0.5} \
        {material add steel -density 7800 -young 2e8 -poisson 0.3 -restitution 0.5 -friction 0.3} \
        {wall add plane -normal {0 0 1} -name floor} \
        {wall add finite -point {0 0 1} -normal {0 0 -1} -axis {1 0 0} -halfextents {0.5 0.25} -tags lids} \
        {wall add box -point {1 0 0} -halfextents {0.1 0.2 0.3}} \
        {wall add drum -point {0 0 0} -radius 0.5 -axis {0 1 0} -halflength 0.2} \
        {element add -radius 0.01 -position {0 0 0.0105} -name first -tags grains} \
        {element add -radius 0.01 -position {0.02 0 0.0105} -tags grains} \
        {element add -radius 0.005 -position {0.1 0.1 0.1} -material steel} \
        {bond model pointspring glue -kn 1e5 -ks 1e5 -tensile 1 -shear 1} \
        {bond add -model glue -gap 1e-3} \
        {behavior add gravity} \
        {behavior add load -element 0 -force {0 0 1e-4}} \
        {inlet add feed -region {box {-0.1 -0.1 0.2} {0.1 0.1 0.3}} -radius 0.002 -rate 10} \
        {sink add drain -region {box {-1 -1 -1} {1 1 -0.5}}} \
        [list dump every -steps 1000 -dir [file join $dir dumps]] \
        {series every -steps 1000 -quantities {time kinetic}} \
        {sim save base.ckpt} {dump lammps base.data} {snapshot write base.png -size 16x12} \
        {sim keep base}
}

# Writes the bond file the valid calls of bond file read (a pair of the scene's elements).
# Returns its path.
proc writePairsFile {path} {
    set f [open $path w]
    chan puts $f "first 1"
    close $f
    return $path
}

# Returns the number of components of a vector parameter in a 3D scene.
proc vectorLength {p} {
    set n [dict get $p length]
    expr {$n > 0 ? $n : 3}
}

# Returns a word that the parameter's pipe accepts (its default when it has one).
proc validWord {decl p} {
    set key "[dict get $decl command] [dict get $p name]"
    if {[dict exists $::valid::byParam $key]} {return [dict get $::valid::byParam $key]}
    if {[dict get $p hasdefault]} {return [dict get $p default]}
    set label [dict get $p label]
    if {[dict exists $::valid::byLabel $label]} {
        set w [dict get $::valid::byLabel $label]
        # A word that depends on the scene: the first id a listing command returns.
        if {[lindex $w 0] eq "first-of"} {
            if {[catch {lindex [uplevel #0 [lrange $w 1 end]] 0} w]} {set w 0}
        }
        return $w
    }
    set lo [dict get $p min]
    set hi [dict get $p max]
    switch -- [dict get $p kind] {
        real {
            if {$lo ne "" && $hi ne ""} {return [expr {($lo + $hi) / 2.0}]}
            if {$lo ne ""} {return [expr {$lo + 1.0}]}
            if {$hi ne ""} {return [expr {$hi - 1.0}]}
            return 0.01
        }
        integer {
            if {$lo ne ""} {return [expr {[dict get $p minopen] ? int($lo) + 1 : int($lo)}]}
            if {$hi ne ""} {return [expr {int($hi) - 1}]}
            return 1
        }
        boolean {return 0}
        choice {return [lindex [dict get $p choices] 0]}
        name {return fresh}
        text {return x}
        vector {return [lreplace [lrepeat [vectorLength $p] 0] end end 1]}
        reals {return 0.001}
        integers {return 1}
    }
    return x
}

# Returns s with the characters string match treats specially escaped.
proc globQuote {s} {
    string map {\\ \\\\ * \\* ? \\? [ \\[ ] \\]} $s
}

# Returns the bad words of one parameter as a list of {word mustfail pattern}: mustfail is 1
# when the declared type refuses the word, and pattern, when not empty, is the glob pattern
# the error message must match (Tcl's wording for that refusal). Words the type admits (an
# absurd magnitude, zero, an empty text) come with mustfail 0: they may be accepted.
proc badWords {p} {
    set n [dict get $p name]
    set lo [dict get $p min]
    set hi [dict get $p max]
    set out {}
    # Returns the glob pattern of `bad <n> "<word>": <rest>`.
    set bad {apply {{n w rest} {return "bad $n \"[globQuote $w]\": $rest"}}}
    switch -- [dict get $p kind] {
        real {
            foreach w {abc {} 1.5x {1 2} 0x} {
                lappend out [list $w 1 [{*}$bad $n $w "expected floating-point number"]]
            }
            foreach w {NaN Inf -Inf} {
                lappend out [list $w 1 [{*}$bad $n $w "must be a finite number"]]
            }
            set candidates {1e300 1e308 -1e308 1e-300 -1e-300 -1 0}
            if {$lo ne ""} {lappend candidates [expr {[dict get $p minopen] ? $lo : $lo - 1}]}
            if {$hi ne ""} {lappend candidates [expr {[dict get $p maxopen] ? $hi : $hi + 1}]}
            lappend out {*}[boundaryWords $p $candidates]
        }
        integer {
            foreach w {abc {} 1.5 NaN 1e300 99999999999999999999 0x} {
                lappend out [list $w 1 [{*}$bad $n $w "expected integer"]]
            }
            set candidates {-1 0}
            if {$lo ne ""} {
                lappend candidates [expr {int($lo) - ([dict get $p minopen] ? 0 : 1)}] \
                    -9223372036854775808
            }
            if {$hi ne ""} {
                lappend candidates [expr {int($hi) + ([dict get $p maxopen] ? 0 : 1)}] \
                    9223372036854775807
            }
            lappend out {*}[boundaryWords $p $candidates]
        }
        boolean {
            foreach w {maybe {} 2.5 NaN} {
                lappend out [list $w 1 [{*}$bad $n $w "expected boolean value"]]
            }
        }
        choice {
            foreach w {nosuch {} NaN} {
                lappend out [list $w 1 "* $n \"[globQuote $w]\": must be *"]
            }
        }
        name {
            foreach w {7up {} {a b} a\{b} {
                lappend out [list $w 1 [{*}$bad $n $w "*"]]
            }
            lappend out [list nosuch_thing 0 ""]
        }
        text {
            foreach w {{} abc \{ {a b}} {lappend out [list $w 0 ""]}
        }
        vector {
            set k [vectorLength $p]
            foreach w [list {} [lrepeat [expr {$k - 1}] 1] [lrepeat [expr {$k + 1}] 1]] {
                lappend out [list $w 1 [{*}$bad $n $w "expected a vector of $k numbers but got *"]]
            }
            set rest [lrepeat [expr {$k - 1}] 0]
            lappend out [list [list abc {*}$rest] 1 [{*}$bad $n [list abc {*}$rest] "expected floating-point number but got \"abc\""]]
            foreach c {NaN Inf -Inf} {
                lappend out [list [list $c {*}$rest] 1 [{*}$bad $n $c "must be a finite number"]]
            }
            lappend out [list \{ 1 [{*}$bad $n \{ "unmatched open brace in list"]]
            foreach c {1e300 1e308 -1e308 1e-300 0 -1} {
                lappend out [list [lrepeat $k $c] 0 ""]
            }
        }
        reals {
            lappend out [list {1 abc} 1 [{*}$bad $n {1 abc} "expected floating-point number but got \"abc\""]]
            lappend out [list {1 NaN} 1 [{*}$bad $n NaN "must be a finite number"]]
            lappend out [list \{ 1 [{*}$bad $n \{ "unmatched open brace in list"]]
            foreach w {{} 1e300 -1 0 1e-300} {lappend out [list $w 0 ""]}
        }
        integers {
            lappend out [list {1 1.5} 1 [{*}$bad $n {1 1.5} "expected integer but got \"1.5\""]]
            lappend out [list \{ 1 [{*}$bad $n \{ "unmatched open brace in list"]]
            foreach w {{} -1 0 99999} {lappend out [list $w 0 ""]}
        }
        custom {
            foreach w [customBadWords [dict get $p label]] {lappend out [list $w 1 ""]}
            foreach w {{} abc NaN Inf \{ -1 0 1e300 1e-300} {lappend out [list $w 0 ""]}
        }
    }
    return $out
}

# Returns the candidate numbers as bad words of p: those outside its declared range must be
# refused (`bad <name> "<word>": must be ...`), the others may be accepted.
proc boundaryWords {p candidates} {
    set out {}
    foreach w [lsort -unique $candidates] {
        if {[outsideRange $p $w]} {
            lappend out [list $w 1 "bad [dict get $p name] \"[globQuote $w]\": must be *"]
        } else {
            lappend out [list $w 0 ""]
        }
    }
    return $out
}

# Returns 1 if the number w lies outside the parameter's declared range.
proc outsideRange {p w} {
    set lo [dict get $p min]
    set hi [dict get $p max]
    if {$lo ne "" && ([dict get $p minopen] ? !($w > $lo) : !($w >= $lo))} {return 1}
    if {$hi ne "" && ([dict get $p maxopen] ? !($w < $hi) : !($w <= $hi))} {return 1}
    return 0
}

# Returns the words a custom type must refuse, by its label: unknown names of things, lists of
# the wrong length, broken lists.
proc customBadWords {label} {
    switch -- $label {
        element - wall {return {nosuch 999999 4294967296}}
        material - {kept scene} - model - law {return {nosuch}}
        behavior {return {999999 nosuch}}
        tag - {list of tags} {return {7up {a 7up}}}
        spin - {vector of expressions} - {spin of expressions} {return {{1 2} {1 2 3 4}}}
        region {
            return {nosuch {box {0 0 0}} {box {0 0 0} {NaN 1 1}} {sphere {0 0 0} -1}
                {box {0 0 0} {1e300 1 1}} {cylinder {0 0 0} {0 0 0} 1 1} {sphere {0 0 0}}}
        }
        {size distribution} {
            return {-1 nosuch {uniform 1} {uniform 2 1} {normal 1 -1} {powerlaw 1 2 1e308}
                {discrete 1} {discrete 1 -1}}
        }
        {list of element pairs} {return {{{first 999999}} {{first}} {{first first}}}}
        {list of parts} - {list of fields} - quantity - quantities - {list of quantities} {
            return {nosuch}
        }
        {series id} - {dump id} - {snapshot id} {return {999999 nosuch}}
        WxH {return {0x0 -1x5 100x 1e300x1}}
        {{px py pz nx ny nz}} {return {{0 0 0 0 0 0} {1 2 3}}}
        real|auto {return {-1 NaN nosuch}}
    }
    return {}
}

# Returns the cases of one command that give one parameter a bad word: a list of dicts {decl
# param word mustfail pattern}; callWith makes each one's call (when it runs, so that the words
# naming things of the scene are those of the scene then).
proc badCases {decl} {
    set cases {}
    foreach p [dict get $decl params] {
        if {[dict get $p role] eq "flag"} continue
        foreach bw [badWords $p] {
            lassign $bw word mustfail pattern
            lappend cases [dict create decl $decl param [dict get $p name] word $word \
                mustfail $mustfail pattern $pattern]
        }
    }
    return $cases
}

# Returns the words of a call of decl's command: valid words for what it requires (and the
# options valid::extra adds), `word` for the parameter named `tested` (an option, or a
# positional in its place). An exclusive group that needs one member gets the tested parameter
# when it is a member, else its first member.
proc callWith {decl tested word} {
    set call [dict get $decl command]
    set extra {}
    if {[dict exists $::valid::extra $call]} {
        dict for {o w} [dict get $::valid::extra $call] {
            if {$o ne "-$tested"} {lappend extra $o $w}
        }
    }
    set needed {}
    foreach g [dict get $decl exclusive] {
        if {![dict get $g requireone]} continue
        set names [dict get $g names]
        lappend needed [expr {$tested in $names ? $tested : [lindex $names 0]}]
    }
    set options {}
    foreach p [dict get $decl params] {
        set n [dict get $p name]
        set role [dict get $p role]
        if {$role in {positional variadic}} {
            if {$n eq $tested} {
                lappend call $word
            } elseif {[dict get $p required]} {
                lappend call [validWord $decl $p]
            }
            continue
        }
        if {$n eq $tested} {
            lappend options -$n $word
        } elseif {$role eq "flag" && $n in $needed} {
            lappend options -$n
        } elseif {[dict get $p required] || $n in $needed} {
            lappend options -$n [validWord $decl $p]
        }
    }
    return [concat $call $extra $options]
}
