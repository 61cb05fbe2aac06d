#include "cmd/session.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <fstream>

#include "cmd/words.hpp"
#include "core/atomic_file.hpp"
#include "core/interrupt.hpp"
#include "core/name_lookup.hpp"
#include "mpi/error_bytes.hpp"
#include "core/tag_table.hpp"

namespace demlab::cmd {

void Session::requireScene() const {
  if (!sim) throw Error("no simulation: use \"sim new\" first", {"STATE", "NOSIM"});
}

void Session::beginInterruptible() {
  if (interruptDepth_++ == 0) {
    stop = false;
    outerInterruptFlag_ = setInterruptFlag(&stop);
  }
  catchSigint();
}

void Session::endInterruptible() {
  releaseSigint();
  if (--interruptDepth_ == 0) setInterruptFlag(outerInterruptFlag_);
}

sim::Simulation& Session::scene() const {
  requireScene();
  return *sim;
}

const mpi::Communicator& ranksOf(const sim::Simulation& s) {
  return s.distributed() ? mpi::Communicator::world() : mpi::Communicator::self();
}

Value fromHolder(const sim::Simulation& s, std::optional<Value> mine, const Error& missing) {
  if (!s.distributed()) {
    if (!mine) throw missing;
    return std::move(*mine);
  }
  // One byte says whether a rank holds it: a value's string form may be empty.
  std::vector<char> bytes;
  if (mine) {
    const std::string text = toString(*mine);
    bytes.push_back(1);
    bytes.insert(bytes.end(), text.begin(), text.end());
  }
  for (std::vector<char>& b : ranksOf(s).gatherBytes(bytes)) {
    if (b.empty()) continue;
    if (mine) return std::move(*mine);
    return Value(std::string(b.begin() + 1, b.end()));
  }
  throw missing;
}

void togetherOnRanks(const sim::Simulation& s, const std::function<void()>& work) {
  if (!s.distributed()) return work();
  // A failure travels as its message and code words, each ended by a NUL.
  std::vector<char> mine;
  try {
    work();
  } catch (const Error& e) {
    mpi::appendErrorBytes(e, mine);
  }
  const std::vector<std::vector<char>> all = ranksOf(s).gatherBytes(mine);
  for (std::size_t rank = 0; rank < all.size(); ++rank) {
    if (all[rank].empty()) continue;
    throw mpi::errorFromBytes(all[rank], 0, " (on rank " + std::to_string(rank) + ")");
  }
}

std::int64_t scriptId(std::uint32_t index, std::uint32_t generation) {
  return Handle<struct AnyKind>{index, generation}.scriptId();
}

namespace {

// Returns the handle `word` names (an id, or a name resolved by find), checked by probe.
template <class H, class Find, class Probe>
H lookup(std::string_view word, std::string_view kind, Find find, Probe probe) {
  std::int64_t id;
  if (readInt(word, id)) {
    H h = fromScriptId<H>(id);
    bool ok = id >= 0;
    if (ok) {
      try {
        probe(h);
      } catch (const Error&) {
        ok = false;
      }
    }
    if (!ok)
      throw Error("no " + std::string(kind) + " with id " + std::string(word),
                  {"LOOKUP", codeWord(kind)});
    return h;
  }
  try {
    return find(std::string(word));
  } catch (const Error&) {
    throw Error("no " + std::string(kind) + " named \"" + std::string(word) + "\"",
                {"LOOKUP", codeWord(kind)});
  }
}

}  // namespace

// Returns a completion source: the names `of` lists from the session's scene, none without one.
PipeType::Candidates sceneWords(std::vector<std::string> (sim::Simulation::*of)() const) {
  return [of](const Context& c) {
    const Session& s = session(c);
    return s.sim ? ((*s.sim).*of)() : std::vector<std::string>{};
  };
}

PipeType elementRef() {
  return custom("element", [](std::string_view w, const Param&, const Context& c) -> std::any {
    const sim::Simulation& s = session(c).scene();
    return lookup<sim::ElementId>(
        w, "element", [&](const std::string& n) { return s.findElement(n); },
        [&](sim::ElementId h) {
          // A distributed scene: the rank holding it checks it, in the command (fromHolder).
          if (!s.distributed()) s.element(h);
        });
  }).complete(sceneWords(&sim::Simulation::elementNames));
}

PipeType wallRef() {
  return custom("wall", [](std::string_view w, const Param&, const Context& c) -> std::any {
    const sim::Simulation& s = session(c).scene();
    return lookup<sim::WallId>(
        w, "wall", [&](const std::string& n) { return s.findWall(n); },
        [&](sim::WallId h) { s.wall(h); });
  }).complete(sceneWords(&sim::Simulation::wallNames));
}

PipeType materialRef() {
  PipeType t =
      custom("material", [](std::string_view w, const Param&, const Context& c) -> std::any {
        auto names = session(c).scene().materialNames();
        if (std::find(names.begin(), names.end(), w) == names.end()) {
          throw Error("no material named \"" + std::string(w) + "\"", {"LOOKUP", "MATERIAL"});
        }
        return std::string(w);
      });
  return t.complete(sceneWords(&sim::Simulation::materialNames));
}

PipeType behaviorRef() {
  return custom("behavior", [](std::string_view w, const Param&, const Context& c) -> std::any {
    std::int64_t id;
    if (readInt(w, id) && id >= 0) {
      auto h = fromScriptId<sim::BehaviorId>(id);
      for (const auto& b : session(c).scene().behaviors())
        if (b.id == h) return h;
    }
    throw Error("no behavior with id \"" + std::string(w) + "\"", {"LOOKUP", "BEHAVIOR"});
  });
}

// A regular file that can be read and fits in memory; value: the path. A device such as
// /dev/zero, or a file larger than a quarter of the machine's memory, is refused before a byte
// is read (a checkpoint is read whole, then decoded into a scene of about the same size).
PipeType readableFile() {
  return custom("file", [](std::string_view w, const Param&, const Context&) -> std::any {
    const std::string path(w);
    struct stat st;
    if (stat(path.c_str(), &st) != 0)
      throw Error("couldn't open \"" + path + "\": " + posixMessage(errno), {"IO", "OPEN"});
    if (!S_ISREG(st.st_mode))
      throw Error("couldn't read \"" + path + "\": not a regular file", {"IO", "OPEN"});
    const double memory = double(sysconf(_SC_PHYS_PAGES)) * double(sysconf(_SC_PAGE_SIZE));
    if (memory > 0 && double(st.st_size) > memory / 4) {
      throw Error("couldn't read \"" + path + "\": " + std::to_string(st.st_size) +
                      " bytes is more than a quarter of this machine's memory",
                  {"IO", "SIZE"});
    }
    if (!std::ifstream{path, std::ios::binary})
      throw Error("couldn't open \"" + path + "\": permission denied", {"IO", "OPEN"});
    return path;
  });
}

PipeType lawChoice() {
  PipeType t = custom("law", [](std::string_view w, const Param& p, const Context&) -> std::any {
    static const std::vector<std::string> laws{"linear", "hertz_mindlin"};
    return sim::lawFromName(matchChoice(w, laws, p.name, {"VALUE", codeWord(p.name)}));
  });
  t.choices = {"linear", "hertz_mindlin"};
  return t;
}

PipeType tagList() {
  return custom("list of tags", [](std::string_view w, const Param&, const Context&) -> std::any {
    for (const std::string& t : splitList(w)) checkTagName(t);
    return std::string(w);
  }).complete(sceneWords(&sim::Simulation::tagNames));
}

PipeType tagName() {
  return custom("tag", [](std::string_view w, const Param&, const Context&) -> std::any {
    checkTagName(w);
    return std::string(w);
  }).complete(sceneWords(&sim::Simulation::tagNames));
}

PipeType spin() {
  return custom("spin", [](std::string_view w, const Param& p, const Context& c) -> std::any {
    Param q = p;
    q.type = vector(c.dimension() == 2 ? 1 : 3);
    return convertWord(w, q, c);
  });
}

sim::Vec3d vec3(const std::vector<double>& v, bool isSpin) {
  sim::Vec3d x{0, 0, 0};
  if (isSpin && v.size() == 1) {
    x[2] = v[0];
    return x;
  }
  for (std::size_t k = 0; k < v.size() && k < 3; ++k) x[k] = v[k];
  return x;
}

Value vecValue(const sim::Vec3d& x, int d, bool isSpin) {
  if (isSpin) return d == 2 ? Value(x[2]) : Value(Reals{{x[0], x[1], x[2]}, 0});
  return Value(Reals{{x.begin(), x.begin() + d}, 0});
}

}  // namespace demlab::cmd
