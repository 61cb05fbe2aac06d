// MaterialDef::check and formatReal.
#include "physics/material.hpp"

#include <charconv>
#include <cmath>

#include "core/error.hpp"

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
  if (!(density > 0 && std::isfinite(density))) {
    bad("density", density, "a positive number", "DENSITY");
  }
  if (!(young > 0 && (std::isfinite(young) || isRigid()))) {
    bad("Young's modulus", young, "a positive number", "YOUNG");
  }
  if (!(poisson > -1 && poisson < 0.5)) {
    bad("Poisson's ratio", poisson, "a number greater than -1 and less than 0.5", "POISSON");
  }
  if (!(restitution > 0 && restitution <= 1)) {
    bad("restitution", restitution, "a number greater than 0 and at most 1", "RESTITUTION");
  }
  if (!(friction >= 0 && std::isfinite(friction))) {
    bad("friction", friction, "a non-negative number", "FRICTION");
  }
  if (!(rollingFriction >= 0 && std::isfinite(rollingFriction))) {
    bad("rolling friction", rollingFriction, "a non-negative number", "ROLLINGFRICTION");
  }
  if (!(cohesion >= 0 && std::isfinite(cohesion))) {
    bad("cohesion", cohesion, "a non-negative number", "COHESION");
  }
  if (!(normalStiffness >= 0 && std::isfinite(normalStiffness))) {
    bad("normal stiffness", normalStiffness, "a non-negative number", "NORMALSTIFFNESS");
  }
  if (!(shearStiffness >= 0 && std::isfinite(shearStiffness))) {
    bad("shear stiffness", shearStiffness, "a non-negative number", "SHEARSTIFFNESS");
  }
  if (shearStiffness > 0 && normalStiffness == 0) {
    bad("shear stiffness", shearStiffness, "0 when the normal stiffness is 0 (derived)",
        "SHEARSTIFFNESS");
  }
}

}  // namespace demlab::physics
