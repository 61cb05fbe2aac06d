// The run functions of the verification cases, one per row of the case table (case_table.cpp).
// Each returns the case's CaseResult at spec (verify.hpp); see each case's description there.
#pragma once

#include "verify/verify.hpp"

namespace demlab::verify {

CaseResult impactLinearPlane(const RunSpec& spec);  // case_impact.cpp
CaseResult impactLinearSphere(const RunSpec& spec);
CaseResult impactHertzPlane(const RunSpec& spec);
CaseResult impactHertzSphere(const RunSpec& spec);
CaseResult obliqueSliding(const RunSpec& spec);  // case_oblique.cpp
CaseResult obliqueSweep(const RunSpec& spec);
CaseResult inclineRolling(const RunSpec& spec);  // case_rolling.cpp
CaseResult inclineSliding(const RunSpec& spec);
CaseResult slideToRoll(const RunSpec& spec);
CaseResult bounce(const RunSpec& spec);      // case_bounce.cpp
CaseResult elasticGas(const RunSpec& spec);  // case_gas.cpp

}  // namespace demlab::verify
