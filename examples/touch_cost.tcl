# The cost of the touch correction (module touch, doc/design.md "Touch and release"): a bed of
# 8000 spheres (r = 1 mm on a lattice of pitch 2.05 r, random speeds up to 0.05 m/s per axis,
# E = 5e6 Pa, restitution 0.5, friction 0.5, Hertz-Mindlin, gravity) falls and bounces in a box
# of five planes, 250 steps at the automatic time step, with the correction off or on.
#
#   build/demlab examples/touch_cost.tcl ?on|off? ?steps?
#
# It prints the run's report (steps 0: only the set-up, to subtract). For the
# load-independent figure, count instructions:
#   valgrind --tool=callgrind build/demlab examples/touch_cost.tcl off
#   valgrind --tool=callgrind build/demlab examples/touch_cost.tcl on

set touch [expr {[llength $argv] ? [lindex $argv 0] : "on"}]
set steps [expr {[llength $argv] > 1 ? [lindex $argv 1] : 250}]
sim new -dim 3
material add m -density 2500 -young 5e6 -poisson 0.3 -restitution 0.5 -friction 0.5
module touch $touch
set r 0.001
set n 20
expr {srand(7)}
for {set i 0} {$i < $n} {incr i} {
    for {set j 0} {$j < $n} {incr j} {
        for {set k 0} {$k < $n} {incr k} {
            set v {}
            foreach _ {1 2 3} {lappend v [expr {0.05 * (2 * rand() - 1)}]}
            element add -radius $r -velocity $v -position [list \
                [expr {(2.05 * $i + 1.2) * $r}] [expr {(2.05 * $j + 1.2) * $r}] \
                [expr {(2.05 * $k + 1.2) * $r}]]
        }
    }
}
set side [expr {2.05 * $n * $r + 0.4 * $r}]
wall add plane -normal {0 0 1}
wall add plane -normal {1 0 0}
wall add plane -normal {0 1 0}
wall add plane -normal {-1 0 0} -point [list $side 0 0]
wall add plane -normal {0 -1 0} -point [list 0 $side 0]
behavior add gravity
puts "module touch $touch: [module list]"
if {$steps > 0} {sim run -steps $steps}
