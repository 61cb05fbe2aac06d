// Vectors whose components are numbers or Tcl expressions in $t: a load's force and torque, a
// wall's velocity and angular velocity. The expressions become TimeFunctions through
// Session::timeFunction (a Tcl interpreter's), tried at the scene's time before anything changes.
#pragma once

#include <array>
#include <string>

#include "cmd/command.hpp"
#include "cmd/pipe.hpp"
#include "cmd/session.hpp"
#include "sim/simulation.hpp"

namespace demlab::cmd {

// Returns the pipe reading such a vector (D numbers or expressions; a spin: 1 in 2D, 3 in 3D);
// its value is the words.
PipeType timeVector(bool isSpin);

// Fills constant (numbers, each checked finite; the scene checks their range) and fns
// (expressions, tried at the scene's time) from the words of option opt; a component that is
// an expression sets its constant to its value now when valueNow, else leaves it. Throws
// VALUE <OPT> (a bad number; an expression that fails now or gives a value beyond bound; no
// interpreter). Changes nothing else.
void timeComponents(Call& c, const std::string& opt, bool isSpin, const TimeBound& bound,
                    sim::Vec3d& constant, std::array<sim::TimeFunction, 3>& fns, bool valueNow);

}  // namespace demlab::cmd
