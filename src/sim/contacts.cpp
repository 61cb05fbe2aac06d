// makeContactModules: picks the instantiation of the contact loops for a scene, once when its
// loop is built (law x history x rotation).
#include "sim/contacts.hpp"

namespace demlab::sim {

namespace {

template <int D, int Law, bool History, bool Rotation>
void addPair(std::vector<std::unique_ptr<SimModule<D>>>& out, bool walls) {
  out.push_back(std::make_unique<GrainContactModule<D, Law, History, Rotation>>());
  if (walls) out.push_back(std::make_unique<WallContactModule<D, Law, History, Rotation>>());
}

template <int D, int Law>
void addForLaw(std::vector<std::unique_ptr<SimModule<D>>>& out, bool history, bool rotation,
               bool walls) {
  if (history) {
    rotation ? addPair<D, Law, true, true>(out, walls) : addPair<D, Law, true, false>(out, walls);
  } else {
    rotation ? addPair<D, Law, false, true>(out, walls) : addPair<D, Law, false, false>(out, walls);
  }
}

}  // namespace

template <int D>
std::vector<std::unique_ptr<SimModule<D>>> makeContactModules(int law, bool history, bool rotation,
                                                              bool walls) {
  std::vector<std::unique_ptr<SimModule<D>>> out;
  constexpr int kLinear = static_cast<int>(physics::LawKind::Linear);
  constexpr int kHertz = static_cast<int>(physics::LawKind::HertzMindlin);
  if (law == kLinear) {
    addForLaw<D, kLinear>(out, history, rotation, walls);
  } else if (law == kHertz) {
    addForLaw<D, kHertz>(out, history, rotation, walls);
  } else {
    addForLaw<D, -1>(out, history, rotation, walls);
  }
  return out;
}

template std::vector<std::unique_ptr<SimModule<2>>> makeContactModules<2>(int, bool, bool, bool);
template std::vector<std::unique_ptr<SimModule<3>>> makeContactModules<3>(int, bool, bool, bool);

}  // namespace demlab::sim
