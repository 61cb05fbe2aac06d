# Tcl package index for demlab: `package require demlab` loads the stubs-enabled extension
# (libdemlab.so, in this folder), which defines the commands and evaluates the Tcl-level
# library (demlab.tcl, compiled into the extension so the two can never disagree).
if {![package vsatisfies [package provide Tcl] 8.6]} {return}
package ifneeded demlab 0.1 [list load [file join $dir libdemlab[info sharedlibextension]] Demlab]
