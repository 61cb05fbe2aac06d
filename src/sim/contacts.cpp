// makeContactModules: picks the instantiation of the contact loops for a scene, once when its
// loop is built (law x history x rotation).
#include "sim/contacts.hpp"

namespace demlab::sim {

namespace {

template <int D, int Law, bool History, bool Rotation>
void addPair(std::vector<std::unique_ptr<SimModule<D>>>& out, bool walls, long grainPair) {
  out.push_back(std::make_unique<BallContactModule<D, Law, History, Rotation>>(grainPair));
  if (walls) {
    out.push_back(std::make_unique<WallContactModule<D, Law, History, Rotation>>(grainPair));
  }
}

template <int D, int Law>
void addForLaw(std::vector<std::unique_ptr<SimModule<D>>>& out, bool history, bool rotation,
               bool walls, long grainPair) {
  if (history) {
    rotation ? addPair<D, Law, true, true>(out, walls, grainPair)
             : addPair<D, Law, true, false>(out, walls, grainPair);
  } else {
    rotation ? addPair<D, Law, false, true>(out, walls, grainPair)
             : addPair<D, Law, false, false>(out, walls, grainPair);
  }
}

}  // namespace

template <int D>
std::vector<std::unique_ptr<SimModule<D>>> makeContactModules(int law, bool history, bool rotation,
                                                              bool walls, long grainPair) {
  std::vector<std::unique_ptr<SimModule<D>>> out;
  constexpr int kLinear = static_cast<int>(physics::LawKind::Linear);
  constexpr int kHertz = static_cast<int>(physics::LawKind::HertzMindlin);
  if (law == kLinear) {
    addForLaw<D, kLinear>(out, history, rotation, walls, grainPair);
  } else if (law == kHertz) {
    addForLaw<D, kHertz>(out, history, rotation, walls, grainPair);
  } else {
    addForLaw<D, -1>(out, history, rotation, walls, grainPair);
  }
  return out;
}

template std::vector<std::unique_ptr<SimModule<2>>> makeContactModules<2>(int, bool, bool, bool,
                                                                          long);
template std::vector<std::unique_ptr<SimModule<3>>> makeContactModules<3>(int, bool, bool, bool,
                                                                          long);

}  // namespace demlab::sim
