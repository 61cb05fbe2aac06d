// MaterialDef::check and formatReal.
#include "physics/material.hpp"

#include <charconv>
#include <cmath>

#include "core/error.hpp"
#include "core/validity.hpp"

namespace demlab::physics {

std::string formatReal(Real x) {
  if (std::isnan(x)) return "NaN";
  if (std::isinf(x)) return x > 0 ? "Inf" : "-Inf";
  // Shortest round-trip digits, written like C's %g: fixed unless the exponent is below -4 or
  // at least 17 (so 5e6 prints as 5000000, 1e20 as 1e+20, 1e-5 as 1e-05).
  char buf[400];
  auto r = std::to_chars(buf, buf + sizeof buf, x, std::chars_format::scientific);
  const std::string sci(buf, r.ptr);
  const int exp = std::stoi(sci.substr(sci.find('e') + 1));
  if (exp < -4 || exp >= 17) return sci;  // to_chars writes at least two exponent digits
  r = std::to_chars(buf, buf + sizeof buf, x, std::chars_format::fixed);
  return std::string(buf, r.ptr);
}

namespace {

[[noreturn]] void bad(const char* what, Real x, const char* must, const char* code) {
  // Built with += (GCC 12 warns falsely on chains of + at -O3, bug 105329).
  std::string message = "bad ";
  message += what;
  message += " \"";
  message += formatReal(x);
  message += "\": must be ";
  message += must;
  throw Error(std::move(message), {"VALUE", code});
}

}  // namespace

void MaterialDef::check() const {
  // Each test is written so that NaN fails it (comparisons with NaN are false).
  using validity::inRange;
  if (!inRange(density, validity::kMinDensity, validity::kMaxDensity)) {
    bad("density", density, "a number from 1e-06 to 1000000000", "DENSITY");
  }
  if (!(inRange(young, validity::kMinYoung, validity::kMaxYoung) || isRigid())) {
    bad("Young's modulus", young, "a number from 0.001 to 1e+15 (Inf: rigid, for walls)",
        "YOUNG");
  }
  if (!(poisson > -1 && poisson < 0.5)) {
    bad("Poisson's ratio", poisson, "a number greater than -1 and less than 0.5", "POISSON");
  }
  if (!(restitution > 0 && restitution <= 1)) {
    bad("restitution", restitution, "a number greater than 0 and at most 1", "RESTITUTION");
  }
  if (!inRange(friction, 0, validity::kMaxCoefficient)) {
    bad("friction", friction, "a number from 0 to 1e+30", "FRICTION");
  }
  if (!inRange(rollingFriction, 0, validity::kMaxCoefficient)) {
    bad("rolling friction", rollingFriction, "a number from 0 to 1e+30", "ROLLINGFRICTION");
  }
  if (!inRange(cohesion, 0, validity::kMaxCoefficient)) {
    bad("cohesion", cohesion, "a number from 0 to 1e+30", "COHESION");
  }
  if (!inRange(normalStiffness, 0, validity::kMaxCoefficient)) {
    bad("normal stiffness", normalStiffness, "a number from 0 to 1e+30", "NORMALSTIFFNESS");
  }
  if (!inRange(shearStiffness, 0, validity::kMaxCoefficient)) {
    bad("shear stiffness", shearStiffness, "a number from 0 to 1e+30", "SHEARSTIFFNESS");
  }
  if (shearStiffness > 0 && normalStiffness == 0) {
    bad("shear stiffness", shearStiffness, "0 when the normal stiffness is 0 (derived)",
        "SHEARSTIFFNESS");
  }
}

}  // namespace demlab::physics
