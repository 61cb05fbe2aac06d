# checkpoint_bed.tcl save FILE | load FILE: a checkpoint written by any number of ranks and
# loaded on any number (script_ranks.sh runs the pairs). `save` makes falling_bed.tcl's bed
# (bed_scene.tcl), runs it 3000 steps, saves it, and goes on; `load` loads the file and goes
# on the same 1000 steps. Both print (rank 0 alone under mpirun) what compare_runs.tcl compares: a loaded run
# must go on as the saving one did, to round-off when the ranks differ.
lassign $argv mode file
if {$mode eq "save"} {
    source [file join [file dirname [info script]] bed_scene.tcl]
    lassign [makeBed] gone bed
    # A tag, in an order other than the ids', pushed by a load: the checkpoint keeps them.
    element tag kept {*}[lreverse [lrange $bed 10 20]]
    behavior add load -tag kept -force {0 0 1e-4}
    sim run -steps 3000 -quiet
    # Elements removed on the ranks before the save: their slots are free in the checkpoint's
    # handle pool (the next element added takes the last one freed, as the serial scene does).
    element remove [lindex $bed 5] [lindex $bed 800] [lindex $bed 333]
    # A grain fixed and one held vertically: the checkpoint keeps them (under the scripts'
    # handles) for whichever rank will own them.
    element set [lindex $bed 700] -fixed 1
    element set [lindex $bed 701] -block z
    # A grain added named and tagged on the ranks: kept under the handle scripts hold.
    element add -radius 0.001 -position {0.03 0.03 0.05} -name marker -tags kept
    sim save $file
} else {
    sim load $file
}
set ids [lsort -integer [element list]]
set report [sim run -steps 1000 -quiet]
puts "time [sim time]"
puts "count [element count]"
puts "list $ids"
puts "contacts [dict get [query counts] contacts]"
puts "residual [dict get $report residual]"
set e [query energy]
foreach k {kinetic gravitational elastic damping friction wallwork} { puts "$k [dict get $e $k]" }
puts "floorforce [wall get 0 -force]"
puts "floorwork [wall get 0 -work]"
foreach k {0 1 17 600 1196} {
    set id [lindex $ids $k]
    puts "position$k [element get $id -position]"
    puts "velocity$k [element get $id -velocity]"
}
puts "blocked [element get [lindex $ids 697] -blocked] / [element get [lindex $ids 698] -blocked]"
puts "position_fixed [element get [lindex $ids 697] -position]"
puts "reused [element get [expr {2**32}] -position]"
puts "tagged [element list -tag kept] [element get marker -id]"
puts "position_marker [element get marker -position]"
puts "nextid [element add -radius 0.001 -position {0.02 0.02 0.05}]"
