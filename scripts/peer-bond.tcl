# demlab's side of scripts/peer-bond: the 3D unconfined compression of examples/ucs.tcl, which
# writes the bonded sample for the peer (-export PREFIX) before loading it, then one CSV row:
#
#   demlab,elements,bonds,steps,seconds,seconds_per_step,us_per_bond_step,peak_MPa,E_GPa,
#   cpu_seconds,cpu_us_per_bond_step
#
#   build/demlab scripts/peer-bond.tcl PREFIX ?ucs.tcl options ...?
#
# seconds and cpu_seconds are ucs.tcl's: the wall and CPU time of the compression alone (its
# readings included, as the peer's are), not the sample's making.
set prefix [lindex $argv 0]
set argv [list $prefix.ucs.csv -dim 3 -export $prefix {*}[lrange $argv 1 end]]
set r [source [file join [file dirname [info script]] .. examples ucs.tcl]]
set steps [dict get $r steps]
set seconds [dict get $r seconds]
set cpu [dict get $r cpu]
set bonds [dict get $r bonds]
puts [format demlab,%d,%d,%d,%.3f,%.4g,%.4g,%.4g,%.4g,%.3f,%.4g [dict get $r elements] $bonds \
    $steps $seconds [expr {$seconds / $steps}] [expr {1e6 * $seconds / $steps / $bonds}] \
    [expr {[dict get $r peak] / 1e6}] [expr {[dict get $r modulus] / 1e9}] \
    $cpu [expr {1e6 * $cpu / $steps / $bonds}]]
