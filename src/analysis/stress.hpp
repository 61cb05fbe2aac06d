// The Love-Weber average stress of a set of elements (Love 1927, Weber 1966; Christoffersen et
// al. 1981), static (contacts, bonds) and kinetic parts apart:
//   sigma = (1/V) [ sum over contact and bond arms  w  f (x) l  +  sum over elements m v' (x) v' ]
// with compression positive (the soil-mechanics convention: a bed under gravity has positive
// vertical stress; LIGGGHTS and LAMMPS report the opposite sign). For a grain pair the two
// arms add up to f_ab (x) (x_b - x_a), f_ab the force on b; a wall contact has one arm, the
// element's, with the force the wall receives and the branch from the centre to the contact
// point. v' is the velocity less the selection's mass-weighted mean velocity.
#pragma once

#include "analysis/sample.hpp"
#include "analysis/tensor.hpp"

namespace demlab::analysis {

struct StressResult {
  Tensor contact{};  // the contacts' static part, Pa (N/m in 2D)
  Tensor bond{};     // the bonds' static part (zero when the sample has no bonds)
  Tensor kinetic{};  // the kinetic (velocity fluctuation) part
  double volume = 0;
  size_t elements = 0;  // elements in the kinetic sum
  double arms = 0;      // the summed arm weights of the contact sum
  // The forces between elements: contacts and bonds.
  Tensor statics() const {
    Tensor t = contact;
    addScaled(t, bond, 1);
    return t;
  }
  Tensor total() const {
    Tensor t = statics();
    addScaled(t, kinetic, 1);
    return t;
  }
};

// Returns the stress of the selection over volume V (> 0): each contact arm weighted by
// armWeight (the fraction of its branch in the region: the contact's stress is spread along
// its branch, as coarse-graining does, so neighbouring regions add up to their union's), each
// element in the kinetic part counted by selects() (its centre). Changes nothing.
StressResult loveWeberStress(const Sample& s, const Selection& sel, double volume);

}  // namespace demlab::analysis
