// SimLevel, SimModule and SimLoop (thesis chapter 9): one time step is an ordered list of
// modules, each a pluggable stage, and the loop runs them in level order. A scene holds only
// the modules it uses (SimulationManager::buildLoop decides from the scene), so a scene
// without friction runs no history code, one without rotation no rotational update, one
// without walls no wall code; listModules() shows the list. Dispatch is one virtual call per
// module per step; each module loops over its own contiguous arrays.
#pragma once

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstddef>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace demlab::sim {

template <int D>
struct Scene;

// The stages of one velocity-Verlet step, in order. Forces at t+dt need positions at t+dt
// (Predict), walls placed at t+dt (Walls) and the candidate pairs (Detection); Behaviors add
// body forces after the contacts, and Correct closes the step with the second half kick.
// Output modules (snapshots, data files) run last, on the finished step, and only read.
enum class SimLevel { Predict, Walls, Detection, Contacts, Behaviors, Correct, Cleanup, Output };

// Thrown out of a step by pollStep: Ctrl-C asked, and the run holds a copy of the scene to go
// back to, so the half-done step is dropped (SimulationManager::run).
struct StepAbandoned {};

// Throws StepAbandoned when the scene's step may be abandoned and Ctrl-C asked for it. A long
// module calls it between its thread-pool regions (never inside one), so that a step of a very
// large scene answers within a fraction of its own time. Changes nothing.
template <int D>
void pollStep(const Scene<D>& scene) {
  if (scene.abandonOn && scene.abandonOn->load(std::memory_order_relaxed)) throw StepAbandoned{};
}

template <int D>
class SimModule {
 public:
  virtual ~SimModule() = default;
  // Returns the module's name as listModules() shows it.
  virtual std::string_view name() const = 0;
  virtual SimLevel level() const = 0;
  // Runs the module's part of one step on the scene; changes what the module owns.
  virtual void run(Scene<D>& scene) = 0;
  // Returns the bytes of heap the module holds for itself (scratch kept between steps), for
  // Simulation::memory(); 0 for a module that keeps none.
  virtual size_t workingBytes() const { return 0; }
  // Returns true if the module reads the step's contact records (Scene::contacts), which the
  // contact passes then record at every step, not only where something looks.
  virtual bool readsContactRecords() const { return false; }
  // Returns true if the module reads and changes owned elements only, never a distributed
  // run's ghosts: it may then run while the ghosts' forces travel back (placeGhostForceSend).
  virtual bool ownedOnly() const { return false; }
};

template <int D>
class SimLoop {
 public:
  // Replaces the modules; they run in level order, then in the order given.
  void setModules(std::vector<std::unique_ptr<SimModule<D>>> modules) {
    std::stable_sort(modules.begin(), modules.end(),
                     [](const auto& a, const auto& b) { return a->level() < b->level(); });
    modules_ = std::move(modules);
    seconds_.assign(modules_.size(), 0.0);
  }

  // Replaces the modules of one level by `modules` (an empty list drops the level), keeping
  // every other module, its state and its timer; the loop stays in level order. Used to plug
  // output modules into a built loop without rebuilding the physics modules.
  void setLevel(SimLevel level, std::vector<std::unique_ptr<SimModule<D>>> modules) {
    std::vector<std::unique_ptr<SimModule<D>>> kept;
    std::vector<double> secs;
    size_t at = 0;
    for (size_t k = 0; k < modules_.size(); ++k) {
      if (modules_[k]->level() == level) continue;
      if (modules_[k]->level() < level) at = kept.size() + 1;
      kept.push_back(std::move(modules_[k]));
      secs.push_back(seconds_[k]);
    }
    for (auto& m : modules) {
      secs.insert(secs.begin() + static_cast<std::ptrdiff_t>(at), 0.0);
      kept.insert(kept.begin() + static_cast<std::ptrdiff_t>(at), std::move(m));
      ++at;
    }
    modules_ = std::move(kept);
    seconds_ = std::move(secs);
  }

  // Runs one step: every module once, timing each. Changes the scene and the timers. Polls
  // Ctrl-C between the physics modules (pollStep: may throw StepAbandoned, the scene then half
  // stepped); output modules write files, so once they start the step is finished.
  void step(Scene<D>& scene) {
    using Clock = std::chrono::steady_clock;
    auto t0 = Clock::now();
    for (size_t k = 0; k < modules_.size(); ++k) {
      if (k > 0 && modules_[k]->level() != SimLevel::Output) pollStep(scene);
      modules_[k]->run(scene);
      const auto t1 = Clock::now();
      seconds_[k] += std::chrono::duration<double>(t1 - t0).count();
      t0 = t1;
    }
  }

  // Runs only the force stages (walls, detection, contacts, behaviors) once, untimed: the
  // forces at the current time that velocity Verlet's first step needs. Changes the scene.
  // Polls Ctrl-C between them as step() does.
  void forcesOnly(Scene<D>& scene) {
    for (const auto& m : modules_) {
      const SimLevel l = m->level();
      if (l == SimLevel::Walls || l == SimLevel::Detection || l == SimLevel::Contacts ||
          l == SimLevel::Behaviors) {
        pollStep(scene);
        m->run(scene);
      }
    }
  }

  // Returns true if some module reads the contact records of every step.
  bool readsContactRecords() const {
    return std::any_of(modules_.begin(), modules_.end(),
                       [](const auto& m) { return m->readsContactRecords(); });
  }

  // Returns the module names in run order.
  std::vector<std::string> names() const {
    std::vector<std::string> out;
    for (const auto& m : modules_) out.emplace_back(m->name());
    return out;
  }

  // Returns the seconds spent in each module since the last resetTimers(), in run order.
  const std::vector<double>& seconds() const { return seconds_; }
  void resetTimers() { seconds_.assign(modules_.size(), 0.0); }
  bool empty() const { return modules_.empty(); }
  // Returns the bytes the modules hold for themselves (SimModule::workingBytes), summed over
  // all modules or those of one level.
  size_t workingBytes() const {
    size_t bytes = 0;
    for (const auto& m : modules_) bytes += m->workingBytes();
    return bytes;
  }
  size_t workingBytes(SimLevel level) const {
    size_t bytes = 0;
    for (const auto& m : modules_) bytes += m->level() == level ? m->workingBytes() : 0;
    return bytes;
  }

 private:
  std::vector<std::unique_ptr<SimModule<D>>> modules_;
  std::vector<double> seconds_;
};

}  // namespace demlab::sim
