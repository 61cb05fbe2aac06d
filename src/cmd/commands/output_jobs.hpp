// The bookkeeping of a command group whose `every` subcommand adds output modules (snapshot,
// dump): which of a scene's outputs are the group's, with the job each one's callback owns;
// the id type its `off` takes; and its `off` command. The callback owns the job; the table
// only watches it, so a removed output's job goes with its callback.
#pragma once

#include <algorithm>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "cmd/commands/commands.hpp"
#include "cmd/words.hpp"

namespace demlab::cmd {

template <class Job>
class OutputJobs {
 public:
  // group: the command group's name ("dump"), used in errors and help.
  explicit OutputJobs(std::string group) : group_(std::move(group)) {}

  // Records that output id of s runs job. Changes the table.
  void add(const sim::Simulation& s, sim::OutputId id, const std::shared_ptr<Job>& job) {
    live()[{&s, id.bits()}] = job;
  }

  // Returns the group's outputs of s with their jobs, in firing order.
  std::vector<std::pair<sim::OutputInfo, std::shared_ptr<Job>>> of(const sim::Simulation& s) {
    std::vector<std::pair<sim::OutputInfo, std::shared_ptr<Job>>> out;
    auto& j = live();
    for (const sim::OutputInfo& o : s.outputs()) {
      auto it = j.find({&s, o.id.bits()});
      if (it == j.end()) continue;
      if (auto p = it->second.lock()) out.emplace_back(o, p);
    }
    return out;
  }

  // Returns the type of an output id as the group's `every` returned it; value: sim::OutputId.
  // Another group's output, or none, is {LOOKUP <GROUP>}.
  PipeType ref() {
    return custom(group_ + " id", [this](std::string_view w, const Param& p, const Context& ctx) {
      std::int64_t id;
      if (readInt(w, id)) {
        const auto h = fromScriptId<sim::OutputId>(id);
        for (auto& [info, job] : of(session(ctx).scene()))
          if (info.id == h) return std::any(h);
      }
      std::string code = group_;
      std::transform(code.begin(), code.end(), code.begin(), ::toupper);
      throw Error("no " + group_ + " output \"" + std::string(w) + "\" (" + p.name +
                      "): see \"" + group_ + " list\"",
                  {"LOOKUP", code});
    });
  }

  // Returns nothing; creates folder dir if it does not exist and runs first (which writes the
  // output's first files there); when first throws, removes the folder if it made it and
  // rethrows. Throws {IO DIR} when the folder cannot be made.
  static void startIn(const std::string& dir, const std::function<void()>& first) {
    namespace fs = std::filesystem;
    std::error_code ec;
    const bool made = !fs::exists(dir, ec) && fs::create_directories(dir, ec);
    if (ec) throw Error("can't create folder \"" + dir + "\": " + ec.message(), {"IO", "DIR"});
    try {
      first();
    } catch (...) {
      if (made) fs::remove_all(dir, ec);
      throw;
    }
  }

  // Declares "<group> off": removes the given outputs of the group (all without ids).
  void declareOff(Registry& r) {
    Command& off = r.add(group_ + " off", "Removes " + group_ +
                                              " outputs (all, or those given); returns how many.");
    off.variadicArg("id", ref(), group_ + " output ids").optional = true;
    off.onRanks = OnRanks::Alike;
    off.run([this](Call& c) {
      sim::Simulation& s = session(c).scene();
      std::vector<sim::OutputId> ids;
      if (c.has("id")) {
        for (auto id : c.all<sim::OutputId>("id"))
          if (std::find(ids.begin(), ids.end(), id) == ids.end()) ids.push_back(id);
      } else {
        for (auto& [info, job] : of(s)) ids.push_back(info.id);
      }
      for (sim::OutputId id : ids) s.removeOutput(id);
      return Value(ids.size());
    });
  }

 private:
  std::map<std::pair<const void*, std::uint64_t>, std::weak_ptr<Job>>& live() {
    std::erase_if(jobs_, [](const auto& kv) { return kv.second.expired(); });
    return jobs_;
  }

  std::string group_;
  std::map<std::pair<const void*, std::uint64_t>, std::weak_ptr<Job>> jobs_;
};

}  // namespace demlab::cmd
