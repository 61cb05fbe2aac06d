// The option table (sim/options.hpp, sim/option_table.hpp): one row per option and the checks
// every value goes through; the rows' checkpoint records are option_io.cpp. The rows of the
// options that existed before the table keep the bytes those options had (Header and Tagged
// stores); a new option takes the Section store.
#include "sim/option_table.hpp"

#include <algorithm>
#include <cmath>
#include <type_traits>

#include "core/validity.hpp"
#include "core/error.hpp"
#include "physics/material.hpp"
#include "sim/scene_io.hpp"

namespace demlab::sim {

namespace {

constexpr std::string_view kIntegrators[] = {"synchronized", "verlet"};
// In the order of the values in sim/law_models.hpp.
constexpr std::string_view kTangential[] = {"history", "none"};
constexpr std::string_view kSwitch[] = {"on", "off", "auto"};
constexpr std::string_view kCurvature[] = {"equivalent", "local"};

// get and set of an option held in one scene field (or a member of one).
template <class T>
double toRaw(const T& x) {
  if constexpr (std::is_enum_v<T>) {
    return static_cast<double>(static_cast<int>(x));
  } else {
    return static_cast<double>(x);
  }
}
template <class T>
void fromRaw(T& field, double x) {
  if constexpr (std::is_enum_v<T>) {
    field = static_cast<T>(static_cast<int>(x));
  } else if constexpr (std::is_same_v<T, bool>) {
    field = x != 0;
  } else {
    field = static_cast<T>(x);
  }
}
template <int D, auto M>
double getField(const Scene<D>& s) {
  return toRaw(s.*M);
}
template <int D, auto M>
void setField(Scene<D>& s, double x) {
  fromRaw(s.*M, x);
}
template <int D, auto M, auto N>
double getMember(const Scene<D>& s) {
  return toRaw(s.*M.*N);
}
template <int D, auto M, auto N>
void setMember(Scene<D>& s, double x) {
  fromRaw(s.*M.*N, x);
}

constexpr double kInf = std::numeric_limits<double>::infinity();

template <int D>
struct Rows {
  using S = Scene<D>;
  using W = WatchdogOptions;
  static constexpr OptionStore kHeader = OptionStore::Header, kTagged = OptionStore::Tagged;
  static constexpr OptionEffect kLoop = OptionEffect::Loop, kSearch = OptionEffect::Search;
  // Header options in the order of their slots; tagged groups' options in their records' order.
  static inline const OptionRow<D> rows[] = {
      {{.group = "integrator",
        .name = "name",
        .type = OptionType::Choice,
        .def = std::string("synchronized"),
        .help = "the integrator: synchronized (the default) or verlet",
        .choices = kIntegrators,
        .store = kHeader},
       getField<D, &S::integrator>,
       setField<D, &S::integrator>},
      {{.group = "rotation",
        .name = "on",
        .type = OptionType::Boolean,
        .def = true,
        .help = "rotate the elements (default 1); off, they keep their orientation and angular "
                "velocity and contact torques are ignored",
        .store = kHeader},
       getField<D, &S::rotationEnabled>,
       setField<D, &S::rotationEnabled>},
      {{.group = "detection",
        .name = "cellfactor",
        .type = OptionType::Real,
        .def = 0.0,
        .help = "CGrid cell = factor x size statistic (0: CGrid's default)",
        .lo = 0,
        .store = kHeader,
        .effect = kSearch},
       getField<D, &S::cellFactor>,
       setField<D, &S::cellFactor>},
      {{.group = "detection",
        .name = "skin",
        .type = OptionType::Real,
        .def = -1.0,
        .help = "Verlet skin (negative: automatic, 0: search every step)",
        .hi = validity::kMaxCoordinate,  // the search's boxes stay finite
        .unit = "m",
        .store = kHeader,
        .effect = kSearch},
       getField<D, &S::skinOption>,
       setField<D, &S::skinOption>},
      {{.group = "detection",
        .name = "margins",
        .type = OptionType::Boolean,
        .def = true,
        .help = "grow the boxes of the few grains much faster than the rest by wider margins "
                "(default 1: fewer searches; 0: half the skin for every grain)",
        .effect = kSearch},
       getField<D, &S::wideMargins>,
       setField<D, &S::wideMargins>},
      {{.group = "watchdog",
        .name = "on",
        .type = OptionType::Boolean,
        .def = true,
        .help = "run the watchdog (default 1)",
        .store = kTagged,
        .effect = kLoop},
       getMember<D, &S::watchdog, &W::enabled>,
       setMember<D, &S::watchdog, &W::enabled>},
      {{.group = "watchdog",
        .name = "overlap",
        .type = OptionType::Real,
        .def = 2.0,
        .help = "largest overlap during a run, as a fraction of the smaller radius (default 2: "
                "a grain gone through another; 0.2 suits stiff materials; 0: no check)",
        .lo = 0,
        .store = kTagged,
        .effect = kLoop},
       getMember<D, &S::watchdog, &W::overlap>,
       setMember<D, &S::watchdog, &W::overlap>},
      {{.group = "watchdog",
        .name = "placed",
        .type = OptionType::Real,
        .def = 0.5,
        .help = "largest overlap of the scene as set up, checked before its first step, and "
                "of what edits placed since, before the next run (default 0.5; 0: no check)",
        .lo = 0,
        .store = kTagged,
        .effect = kLoop},
       getMember<D, &S::watchdog, &W::placed>,
       setMember<D, &S::watchdog, &W::placed>},
      {{.group = "watchdog",
        .name = "energy",
        .type = OptionType::Real,
        .def = 0.5,
        .help = "largest growth of the energy balance as a fraction of the energy scale "
                "(default 0.5; 0: no check)",
        .lo = 0,
        .store = kTagged,
        .effect = kLoop},
       getMember<D, &S::watchdog, &W::energy>,
       setMember<D, &S::watchdog, &W::energy>},
      {{.group = "watchdog",
        .name = "speed",
        .type = OptionType::Boolean,
        .def = true,
        .help = "check that no element outruns the skin (default 1)",
        .store = kTagged,
        .effect = kLoop},
       getMember<D, &S::watchdog, &W::speed>,
       setMember<D, &S::watchdog, &W::speed>},
      {{.group = "touch",
        .name = "on",
        .type = OptionType::Boolean,
        .def = true,
        .help = "integrate each contact's onset and release within its step (default 1)",
        .store = kTagged},
       getField<D, &S::touchCorrection>,
       setField<D, &S::touchCorrection>},
      // The law's sub-model choices (sim/law_models.hpp), in the options section.
      {{.group = "law",
        .name = "tangential",
        .type = OptionType::Choice,
        .def = std::string("history"),
        .help = "history: a tangential spring with Coulomb's limit (the default); none: no "
                "tangential force, whatever the friction coefficients",
        .choices = kTangential},
       getField<D, &S::tangentialModel>,
       setField<D, &S::tangentialModel>},
      {{.group = "law",
        .name = "rolling",
        .type = OptionType::Choice,
        .def = std::string("auto"),
        .help = "rolling resistance: auto (the default) where a pair's rolling friction is "
                "non-zero, on, or off whatever the coefficients",
        .choices = kSwitch},
       getField<D, &S::rollingModel>,
       setField<D, &S::rollingModel>},
      {{.group = "law",
        .name = "cohesion",
        .type = OptionType::Choice,
        .def = std::string("auto"),
        .help = "cohesion: auto (the default) where a pair's cohesion is non-zero, on, or off "
                "whatever the coefficients",
        .choices = kSwitch},
       getField<D, &S::cohesionModel>,
       setField<D, &S::cohesionModel>},
      {{.group = "law",
        .name = "curvature",
        .type = OptionType::Choice,
        .def = std::string("equivalent"),
        .help = "the Hertz radius of pairs with a non-ball element: equivalent (the default), "
                "each body's volume-equivalent sphere's; local, from the two surfaces' own "
                "curvature at the point where the row knows it (superquadrics: the Gaussian "
                "radius, flat parts capped at a_max^2 / a_min), else the equivalent one",
        .choices = kCurvature},
       getField<D, &S::curvatureModel>,
       setField<D, &S::curvatureModel>},
  };
};

constexpr OptionGroup kGroups[] = {
    {"integrator", "Sets the integrator, or returns it.",
     "synchronized (the default; Vyas et al. 2025, physical for static friction at large size "
     "ratios) or verlet (plain velocity Verlet, as LAMMPS and LIGGGHTS).",
     true},
    {"rotation", "Turns element rotation on or off, or returns whether it is on.", "", true},
    {"detection", "Sets contact detection (CGrid) options; returns them as a dict.", ""},
    {"watchdog", "Sets the watchdog's options (on by default); returns them as a dict.",
     "After every step (and before the first step of a run) the watchdog checks that no "
     "position or velocity is non-finite (NAN), no element moves more in one step than the "
     "neighbour search tracks, half the skin (SPEED), no contact overlaps by more than a "
     "fraction of the smaller radius (OVERLAP; another fraction, -placed, for the scene as "
     "set up, before its first step, and for the contacts of elements and walls added, moved "
     "or grown since the last step, before the next run) and the energy balance has not grown by more "
     "than a fraction of the energy scale (ENERGY). When one fails the run stops at that step "
     "with the error DEMLAB WATCHDOG <check>, naming the elements, the likely cause and the "
     "fix; a check that fails before the run's first step leaves the scene unchanged. The "
     "options are part of the scene (saved with it).",
     false, true, kWatchdogTag},
    {"touch",
     "Turns the sub-step treatment of contact onset and release on or off, or returns whether "
     "it is on.",
     "On by default. On, the step in which a contact's normal force begins or ends (a touch, "
     "a release, a damped force reaching its cut-off) receives the integral of the force over "
     "the part of the step the force acted instead of the trapezoid's half step, and the "
     "energy ledger books the damper's loss to match: impacts become second order in the time "
     "step whatever the phase of the touch, and the energy of an elastic gas stops wandering "
     "by O(dt^2) per collision (doc/design.md, \"Touch and release\"). The tangential force is "
     "not corrected. It covers ball-ball and ball-wall contacts (not those of shaped "
     "elements: a shape equal to a ball follows the ball's path only with it off), in periodic "
     "and Lees-Edwards cells too, and costs 2 to 4 % of a dense bed's step "
     "(doc/performance.md). LIGGGHTS has no such correction: turn it off to reproduce "
     "LIGGGHTS. "
     "Part of the scene (saved with it).",
     true, true, kTouchTag},
    {"law", "Selects the contact law's sub-models; returns the choice as a dict.",
     "In the spirit of LAMMPS's pair granular: -normal is the default law (law default; a pair "
     "with its own law keeps it), -damping Hertz's (law damping), -tangential the tangential "
     "model, -rolling and -cohesion whether those sub-models run, -curvature the Hertz radius of shape pairs. auto, their default, runs "
     "one where a pair's coefficient (material -rolling, -cohesion, law coefficients) is "
     "non-zero; off leaves it out whatever the coefficients; on keeps it in the loop. A choice "
     "other than the default is saved with the scene.",
     false, false},
};

// Returns the options' names joined as the command layer lists alternatives.
std::string alternatives(const std::vector<std::string>& items) {
  std::string out;
  for (size_t k = 0; k < items.size(); ++k) {
    if (k) out += items.size() > 2 ? ", " : " ";
    if (k && k + 1 == items.size()) out += "or ";
    out += items[k];
  }
  return out;
}

[[noreturn]] void badValue(const OptionSpec& o, const std::string& word, const std::string& why) {
  std::string code;
  for (char c : o.name) code += static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  throw Error("bad " + std::string(o.name) + " \"" + word + "\": " + why, {"VALUE", code});
}

// Returns x's fault against o's range in the command layer's words, or "" (cmd/pipe.cpp).
std::string rangeFault(const OptionSpec& o, double x) {
  if (!std::isfinite(x)) return "must be a finite number";
  const bool below = o.loOpen ? !(x > o.lo) : !(x >= o.lo);
  const bool above = o.hiOpen ? !(x < o.hi) : !(x <= o.hi);
  if (!below && !above) return "";
  return "must be " + optionRange(o);
}

}  // namespace

template <int D>
std::span<const OptionRow<D>> optionTable() {
  return Rows<D>::rows;
}

std::span<const OptionSpec> optionSpecs() {
  static const std::vector<OptionSpec> specs = [] {
    std::vector<OptionSpec> v;
    for (const OptionRow<3>& r : optionTable<3>()) v.push_back(r.spec);
    return v;
  }();
  return specs;
}

std::span<const OptionGroup> optionGroups() {
  return kGroups;
}

const OptionGroup& findOptionGroup(std::string_view name) {
  std::vector<std::string> names;
  for (const OptionGroup& g : kGroups) {
    if (g.name == name) return g;
    names.emplace_back(g.name);
  }
  std::sort(names.begin(), names.end());
  throw Error("bad module \"" + std::string(name) + "\": must be " + alternatives(names),
              {"LOOKUP", "MODULE"});
}

std::vector<const OptionSpec*> groupOptions(std::string_view group) {
  std::vector<const OptionSpec*> out;
  for (const OptionSpec& o : optionSpecs()) {
    if (o.group == group) out.push_back(&o);
  }
  return out;
}

std::pair<const OptionSpec*, size_t> findOption(std::string_view group, std::string_view name) {
  findOptionGroup(group);
  const auto specs = optionSpecs();
  std::vector<std::string> names;
  for (size_t k = 0; k < specs.size(); ++k) {
    if (specs[k].group != group) continue;
    if (specs[k].name == name) return {&specs[k], k};
    names.emplace_back(1, '-');
    names.back().append(specs[k].name);
  }
  throw Error("bad option \"-" + std::string(name) + "\": must be " + alternatives(names),
              {"VALUE", "OPTION"});
}

std::string optionRange(const OptionSpec& o) {
  if (o.type != OptionType::Real) return "";
  using physics::formatReal;
  const bool lo = std::isfinite(o.lo), hi = std::isfinite(o.hi);
  if (lo && hi) return "between " + formatReal(o.lo) + " and " + formatReal(o.hi);
  if (lo && o.lo == 0) return o.loOpen ? "a positive number" : "a non-negative number";
  if (lo) return std::string(o.loOpen ? "> " : ">= ") + formatReal(o.lo);
  if (hi) return std::string(o.hiOpen ? "< " : "<= ") + formatReal(o.hi);
  return "a finite number";
}

std::string formatOption(const OptionValue& v) {
  if (const bool* b = std::get_if<bool>(&v)) return *b ? "1" : "0";
  if (const double* x = std::get_if<double>(&v)) return physics::formatReal(*x);
  return std::get<std::string>(v);
}

OptionValue checkOption(const OptionSpec& o, const OptionValue& v) {
  switch (o.type) {
    case OptionType::Boolean:
      if (const bool* b = std::get_if<bool>(&v)) return *b;
      if (const double* x = std::get_if<double>(&v); x && (*x == 0 || *x == 1)) return *x != 0;
      badValue(o, formatOption(v), "must be a boolean");
    case OptionType::Real: {
      const double* x = std::get_if<double>(&v);
      if (!x) badValue(o, formatOption(v), "must be a number");
      const std::string fault = rangeFault(o, *x);
      if (!fault.empty()) badValue(o, formatOption(v), fault);
      return *x;
    }
    case OptionType::Choice: {
      const std::string* s = std::get_if<std::string>(&v);
      std::vector<std::string> words(o.choices.begin(), o.choices.end());
      if (s && std::find(words.begin(), words.end(), *s) != words.end()) return *s;
      badValue(o, formatOption(v), "must be " + alternatives(words));
    }
  }
  return v;
}

double optionRaw(const OptionSpec& o, const OptionValue& v) {
  const OptionValue c = checkOption(o, v);
  if (o.type == OptionType::Boolean) return std::get<bool>(c) ? 1 : 0;
  if (o.type == OptionType::Real) return std::get<double>(c);
  const std::string& s = std::get<std::string>(c);
  return static_cast<double>(std::find(o.choices.begin(), o.choices.end(), s) - o.choices.begin());
}

OptionValue optionFromRaw(const OptionSpec& o, double x) {
  if (o.type == OptionType::Boolean) return x != 0;
  if (o.type == OptionType::Real) return x;
  return std::string(o.choices[static_cast<size_t>(x)]);
}

template std::span<const OptionRow<2>> optionTable<2>();
template std::span<const OptionRow<3>> optionTable<3>();

}  // namespace demlab::sim
