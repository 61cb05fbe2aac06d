// SimulationManager<D>: output modules (OutputDef in sim/simulation.hpp). The "outputs" module
// sits at SimLevel::Output, after the step is complete, and exists only while some output does:
// a scene without outputs runs no output code. Adding or removing an output swaps that one level
// of a built loop (SimLoop::setLevel), so the physics modules and their state are untouched and
// a run with outputs is bit-identical to one without.
#include <cmath>

#include "sim/simulation_manager.hpp"

namespace demlab::sim {

namespace {

// Returns true if an output firing every `every` seconds is due at the step that ended at t
// and lasted dt: (t - dt/2, t + dt/2] holds a multiple of every. The half-step window makes
// the choice immune to the rounding of the summed time.
bool dueByTime(double every, double t, double dt) {
  return std::floor((t + 0.5 * dt) / every) > std::floor((t - 0.5 * dt) / every);
}

}  // namespace

template <int D>
class OutputModule final : public SimModule<D> {
 public:
  explicit OutputModule(const SimulationManager<D>& owner) : owner_(owner) {}
  std::string_view name() const override { return "outputs"; }
  SimLevel level() const override { return SimLevel::Output; }
  // Runs the callbacks that are due; changes nothing in the scene (they read it only).
  void run(Scene<D>& s) override {
    struct Firing {
      const SimulationManager<D>& m;
      explicit Firing(const SimulationManager<D>& mm) : m(mm) { m.firingOutputs_ = true; }
      ~Firing() { m.firingOutputs_ = false; }
    } firing(owner_);
    for (const auto& o : owner_.outputs_) {
      const bool due = o.def.everySteps ? s.steps % o.def.everySteps == 0
                                        : dueByTime(o.def.everyTime, s.time, s.stepDt);
      if (due) o.def.callback(owner_);
    }
  }

 private:
  const SimulationManager<D>& owner_;
};

template <int D>
std::vector<std::unique_ptr<SimModule<D>>> SimulationManager<D>::outputModules() const {
  std::vector<std::unique_ptr<SimModule<D>>> m;
  if (!outputs_.empty()) m.push_back(std::make_unique<OutputModule<D>>(*this));
  return m;
}

template <int D>
bool SimulationManager<D>::outputsReadNextStep() const {
  const double dt = s_.stepDt, t = s_.time + dt;
  for (const Output& o : outputs_) {
    if (!o.def.needsContacts) continue;
    if (o.def.everySteps ? (s_.steps + 1) % o.def.everySteps == 0
                         // Three steps wide: the summed time's rounding cannot hide a due step.
                         : std::floor((t + 1.5 * dt) / o.def.everyTime) >
                               std::floor((t - 1.5 * dt) / o.def.everyTime))
      return true;
  }
  return false;
}

template <int D>
OutputId SimulationManager<D>::addOutput(const OutputDef& def) {
  if (firingOutputs_) {
    throw Error("can't add an output from an output callback", {"STATE", "BUSY"});
  }
  const bool bySteps = def.everySteps > 0, byTime = def.everyTime != 0;
  if (bySteps == byTime) {
    throw Error("bad output \"" + def.name +
                    "\": must fire either every so many steps or every so much time",
                {"VALUE", "OUTPUT"});
  }
  if (byTime && !(std::isfinite(def.everyTime) && def.everyTime > 0)) {
    throw Error("bad output interval \"" + std::to_string(def.everyTime) +
                    "\": must be a positive number of seconds",
                {"VALUE", "OUTPUT"});
  }
  if (!def.callback) {
    throw Error("bad output \"" + def.name + "\": it has no callback", {"VALUE", "CALLBACK"});
  }
  const OutputId id = outputPool_.allocate();
  outputs_.push_back({id, def});
  if (!configDirty_) loop_.setLevel(SimLevel::Output, outputModules());
  return id;
}

template <int D>
void SimulationManager<D>::removeOutput(OutputId id) {
  if (firingOutputs_) {
    throw Error("can't remove an output from an output callback", {"STATE", "BUSY"});
  }
  outputPool_.denseIndex(id);  // throws LOOKUP HANDLE for a stale or unknown id
  outputPool_.free(id);
  std::erase_if(outputs_, [id](const Output& o) { return o.id == id; });
  if (!configDirty_) loop_.setLevel(SimLevel::Output, outputModules());
}

template <int D>
std::vector<OutputInfo> SimulationManager<D>::outputs() const {
  std::vector<OutputInfo> out;
  for (const Output& o : outputs_)
    out.push_back({o.id, o.def.name, o.def.everySteps, o.def.everyTime});
  return out;
}

template class SimulationManager<2>;
template class SimulationManager<3>;

}  // namespace demlab::sim
