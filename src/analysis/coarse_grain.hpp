// Coarse-grained continuum fields of the elements (Goldhirsch 2010; Weinhart et al. 2012, as
// MercuryDPM's MercuryCG): with a kernel W of width w,
//   density          rho(r)   = sum_i m_i W(r - r_i)
//   momentum         p(r)     = sum_i m_i v_i W(r - r_i),  velocity V = p / rho (0 where rho = 0)
//   contact stress   sc(r)    = sum over contact arms  -f (x) l  int_0^1 W(r - r_i - s l) ds
//   kinetic stress   sk(r)    = sum_i m_i v_i (x) v_i W(r - r_i) - rho V (x) V
// Stresses compression positive, as the Love-Weber query (stress.hpp): integrated over all
// space, sc gives the Love-Weber contact sum. The line integral along each arm is taken by the
// midpoint rule on pieces no longer than w / 4.
#pragma once

#include "analysis/cg_field.hpp"
#include "analysis/sample.hpp"

namespace demlab::analysis {

enum class CgKernel {
  Gaussian,  // exp(-r^2 / 2w^2), cut at 3w and renormalised so that it integrates to 1
  Lucy       // Lucy's quartic polynomial with compact support of radius w
};

struct CgSpec {
  Vec3d lo{}, hi{};  // the grid: points lo + i h for i = 0 .. floor((hi - lo) / h) per axis
  double spacing = 0;
  double width = 0;
  CgKernel kernel = CgKernel::Gaussian;
};

// Returns the radius beyond which the kernel is zero (3w Gaussian, w Lucy).
double kernelCutoff(const CgSpec& spec);

// Returns the number of grid points spec makes in d dimensions (as a double: it may be huge).
double cgPointCount(const CgSpec& spec, int d);

// Returns the fields above on spec's grid for the elements carrying the selection's tag (and
// the arms of their contacts); its region is not used. Changes nothing.
CgField coarseGrain(const Sample& s, const Selection& sel, const CgSpec& spec);

}  // namespace demlab::analysis
