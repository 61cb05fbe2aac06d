// Micromechanical queries of a region or a tag group (src/analysis): the Love-Weber stress,
// coordination numbers, the fabric tensor, the packing fraction, the mean motion and
// coarse-grained fields. They read the scene and change nothing.
#include <cmath>
#include <unordered_map>

#include "analysis/coarse_grain.hpp"
#include "analysis/motion.hpp"
#include "analysis/packing_fraction.hpp"
#include "analysis/stress.hpp"
#include "analysis/structure.hpp"
#include "cmd/commands/commands.hpp"
#include "cmd/words.hpp"
#include "core/atomic_file.hpp"
#include "io/vtk_xml.hpp"
#include "cmd/words.hpp"

namespace demlab::cmd {

namespace {

// Returns f as VTK image data, with the scene's time as TIME.
io::VtkImageData cgImage(const analysis::CgField& f, const sim::Simulation& sim) {
  io::VtkImageData d;
  for (int k = 0; k < 3; ++k) {
    d.origin[k] = f.origin[size_t(k)];
    d.spacing[k] = f.spacing[size_t(k)] > 0 ? f.spacing[size_t(k)] : 1;
    d.dims[k] = int64_t(f.dims[size_t(k)]);
  }
  for (const analysis::CgArray& a : f.arrays) d.pointData.push_back({a.name, a.components, a.values});
  d.fieldData.push_back({"TIME", 1, std::vector<double>{sim.time()}});
  return d;
}


using analysis::Sample;
using analysis::Selection;
using analysis::Tensor;

// The most grid points `query cg` makes (25 float64 numbers each: 200 MB at this limit).
constexpr double kMaxCgPoints = double(1 << 20);

// Declares -tag and, when withRegion, -region on cmd, with the selection rule in their help.
void addSelectionOptions(Command& cmd, bool withRegion) {
  if (withRegion)
    cmd.option("region", regionType(),
               "{box {lo} {hi}} or {sphere {centre} radius}: what is inside counts (see above)");
  cmd.option("tag", tagName(), "only the elements carrying this tag");
}

// Returns the selection the call's -tag (and, when useRegion, -region) make over s. Throws
// {VALUE TAG} when no element carries the tag and {VALUE REGION} when the region holds no
// selected element's centre. Changes nothing.
Selection selectionOf(Call& c, const Sample& s, bool useRegion) {
  Selection sel;
  if (c.given("tag")) {
    std::unordered_map<uint32_t, size_t> dense;
    for (size_t i = 0; i < s.size(); ++i) dense[s.ids[i].index] = i;
    sel.tagged.assign(s.size(), 0);
    auto tagged = session(c).scene().elementsTagged(c.str("tag"));
    if (tagged.empty()) c.bad("tag", "no element carries it");
    for (sim::ElementId id : tagged) sel.tagged[dense.at(id.index)] = 1;
  }
  if (useRegion && c.given("region")) {
    sel.region = c.get<sim::Region>("region");
    if (analysis::selectedCount(s, sel) == 0)
      c.bad("region", c.given("tag") ? "holds no centre of an element with the tag"
                                     : "holds no element centre");
  }
  if (s.size() == 0) throw Error("no element in the scene to average over", {"STATE", "EMPTY"});
  return sel;
}

// What a query reads: the scene's sample and the selection the call's options make over it.
struct Scope {
  Sample s;
  Selection sel;
};

// Returns the call's Scope (selectionOf with useRegion). Throws as selectionOf; changes nothing.
Scope scopeOf(Call& c, bool useRegion, bool withBonds = false) {
  Scope scope{analysis::gatherSample(session(c).scene(), withBonds), {}};
  scope.sel = selectionOf(c, scope.s, useRegion);
  return scope;
}

// Returns the first d x d block of t as a flat row-major list.
Value tensorValue(const Tensor& t, int d) {
  Reals r;
  for (int i = 0; i < d; ++i)
    for (int j = 0; j < d; ++j) r.data.push_back(t[3 * i + j]);
  return r;
}

// Returns {tensor, mean, deviatoric, q} of t: the mean normal value trace / d is named meanName.
Dict tensorSummary(const Tensor& t, int d, const std::string& meanName) {
  return Dict{{"tensor", tensorValue(t, d)},
              {meanName, analysis::meanNormal(t, d)},
              {"deviatoric", tensorValue(analysis::deviator(t, d), d)},
              {"q", analysis::deviatorMagnitude(t, d)}};
}

// Declares a query at path with its help, -region and -tag, changing nothing. Returns the
// command, for more options and its run function.
Command& addSelectionQuery(Registry& r, const std::string& path, std::string summary,
                           std::string details) {
  Command& cmd = r.add(path, std::move(summary));
  cmd.details = std::move(details);
  addSelectionOptions(cmd, true);
  cmd.changesScene = false;
  cmd.onRanks = OnRanks::Collective;  // (the sample is the whole scene's on every rank)
  return cmd;
}

// Declares a query of the selection's contact network: addSelectionQuery and -walls
// (wallsHelp). Returns the command.
Command& addNetworkQuery(Registry& r, const std::string& path, std::string summary,
                         std::string details, std::string wallsHelp) {
  Command& cmd = addSelectionQuery(r, path, std::move(summary), std::move(details));
  cmd.flag("walls", std::move(wallsHelp));
  return cmd;
}

void addStress(Registry& r) {
  Command& st = addSelectionQuery(
      r, "query stress", "Returns the Love-Weber average stress of a region or tag group as a dict.",
      "sigma = (1/V) [sum over contacts and bonds f (x) l + sum over elements m v' (x) v'], "
      "COMPRESSION POSITIVE (soil-mechanics convention; LIGGGHTS and LAMMPS report tension "
      "positive). l is the branch vector, centre to centre for two elements (a bond's force "
      "acting midway between the surfaces) and centre to contact point for a wall (with the "
      "force the wall receives); each contact and bond counts by the fraction of its branch "
      "inside the region, so neighbouring regions add up to their union. v' is the velocity less "
      "the selection's mass-weighted mean; the kinetic part counts the elements whose centre is "
      "inside. The dict: tensor (d x d, row-major, Pa; N/m in 2D), pressure (trace / d), "
      "deviatoric (tensor - pressure I), q (sqrt(d/(d-1) s:s): sigma_1 - sigma_3 of a triaxial "
      "state), volume, elements. V is the region's volume unless -volume is given; a tag group "
      "without a region needs -volume. Contacts are those recorded at the last step of a run.");
  st.option("volume", real().positive().withUnit("m^3"),
            "the volume the sums are divided by (an area in 2D; default: the region's)");
  st.option("part", choice({"total", "static", "contacts", "bonds", "kinetic"}),
            "static (the forces between elements: contacts and bonds), either of those alone, "
            "kinetic (velocity fluctuations) or the sum of static and kinetic")
      .byDefault("total");
  st.run([](Call& c) {
    const auto [s, sel] = scopeOf(c, true, true);
    if (!c.given("volume") && !sel.region)
      throw Error("query stress needs -region or -volume: a tag group has no volume of its own",
                  {"VALUE", "VOLUME"});
    const int d = s.dim;
    const double V = c.given("volume") ? c.real("volume") : sel.region->volume(d);
    const analysis::StressResult res = analysis::loveWeberStress(s, sel, V);
    const std::string& part = c.str("part");
    const Tensor t = part == "static"     ? res.statics()
                     : part == "contacts" ? res.contact
                     : part == "bonds"    ? res.bond
                     : part == "kinetic"  ? res.kinetic
                                          : res.total();
    Dict out = tensorSummary(t, d, "pressure");
    out.emplace_back("volume", V);
    out.emplace_back("elements", res.elements);
    return Value(out);
  });
}

void addCoordination(Registry& r) {
  Command& co = addNetworkQuery(
      r, "query coordination", "Returns the coordination numbers of a region or tag group as a dict.",
      "z = (summed contacts of the elements) / N, which is 2C/N when no contact leaves the "
      "selection; mechanical = (sum - N1) / (N - N0 - N1) (Thornton 2000), N0 and N1 the "
      "elements with no contact and with one (rattlers). An element counts when its centre is "
      "in the region; its contacts are its distinct partners, selected or not. The dict: z, "
      "mechanical, elements, contacts (the sum), n0, n1.",
      "count contacts with walls too");
  co.run([](Call& c) {
    const auto [s, sel] = scopeOf(c, true);
    const analysis::Coordination z = analysis::coordination(s, sel, c.flag("walls"));
    return Value(Dict{{"z", z.plain},
                      {"mechanical", z.mechanical},
                      {"elements", z.elements},
                      {"contacts", z.ends},
                      {"n0", z.rattlers0},
                      {"n1", z.rattlers1}});
  });
}

void addFabric(Registry& r) {
  Command& fa = addNetworkQuery(
      r, "query fabric", "Returns the fabric tensor of a region or tag group's contacts.",
      "phi = (1/C) sum n (x) n over the contacts (trace 1), each weighted by the fraction of its "
      "branch vector inside the selection. The dict: tensor (d x d, row-major), mean (1/d), "
      "deviatoric (phi - I/d), q (sqrt(d/(d-1) s:s): 0 for an isotropic network), contacts (C).",
      "count contacts with walls too (the wall's normal)");
  fa.run([](Call& c) {
    const auto [s, sel] = scopeOf(c, true);
    const analysis::Fabric f = analysis::fabric(s, sel, c.flag("walls"));
    if (!(f.contacts > 0))
      throw Error("no contact to average: contacts are recorded at the last step of a run",
                  {"STATE", "CONTACTS"});
    Dict out = tensorSummary(f.tensor, s.dim, "mean");
    out.emplace_back("contacts", f.contacts);
    return Value(out);
  });
}

void addPacking(Registry& r) {
  Command& pk = r.add("query packing", "Returns the solid fraction of a region as a dict.");
  pk.details =
      "The elements' volume inside the region (area in 2D) over the region's: a ball across the "
      "boundary counts by the exact volume of its part inside (closed forms in 2D and for a "
      "sphere region; a 3D box integrates the exact area of each slice to 1e-12). Any other shape "
      "counts whole inside and is refused across the boundary. The dict: fraction, solid "
      "(volume), volume (the region's), mass (inside), bulkdensity (mass / volume), elements.";
  pk.option("region", regionType(), "{box {lo} {hi}} or {sphere {centre} radius}").require();
  pk.option("tag", tagName(), "only the elements carrying this tag");
  pk.changesScene = false;
  pk.onRanks = OnRanks::Collective;
  pk.run([](Call& c) {
    const auto [s, sel] = scopeOf(c, false);
    const auto& region = c.get<sim::Region>("region");
    const analysis::PackingResult p = analysis::packing(s, sel, region);
    if (p.straddling >= 0)
      c.bad("region", "element " + std::to_string(scriptId(s.ids[size_t(p.straddling)])) +
                          " is not a ball and crosses its boundary (its part inside is not "
                          "computed)");
    return Value(Dict{{"fraction", p.fraction},
                      {"solid", p.solid},
                      {"volume", p.volume},
                      {"mass", p.mass},
                      {"bulkdensity", p.mass / p.volume},
                      {"elements", p.elements}});
  });
}

void addMotion(Registry& r) {
  Command& mo = addSelectionQuery(
      r, "query motion", "Returns the mean velocity and granular temperature of a region or tag group.",
      "velocity = sum m v / sum m; temperature T = (1/(d N)) sum m |v - velocity|^2 / <m> "
      "(m^2/s^2), <m> the mean mass: equal elements give the variance of a velocity component. "
      "The dict: elements, mass, velocity, temperature, energy (the fluctuation kinetic energy, "
      "J).");
  mo.run([](Call& c) {
    const auto [s, sel] = scopeOf(c, true);
    const analysis::MotionResult m = analysis::meanMotion(s, sel);
    return Value(Dict{{"elements", m.elements},
                      {"mass", m.mass},
                      {"velocity", vecValue(m.velocity, s.dim)},
                      {"temperature", m.temperature},
                      {"energy", m.fluctuationEnergy}});
  });
}

void addCoarseGrain(Registry& r) {
  Command& cg = r.add("query cg", "Coarse-grains the elements onto a regular grid; returns a summary.");
  cg.interruptible = true;
  cg.details =
      "Fields (Goldhirsch 2010): density, momentum, velocity, contactStress and kineticStress "
      "(compression positive, as query stress), with a Gaussian kernel of standard deviation "
      "-width cut at 3 widths (renormalised) or Lucy's of support -width. The grid's points are "
      "lo + i h along each axis up to hi; by default lo and hi are the elements' bounds widened "
      "by the kernel's reach. The dict: origin, spacing, dims, arrays (name and components), "
      "mass (the density's sum times the cell volume: the total mass when the grid covers the "
      "kernels); -field returns one array's values instead (x fastest; 3 per vector and 9 per "
      "tensor, also in 2D).";
  cg.option("width", real().positive().withUnit("m"), "the kernel's width").require();
  cg.option("spacing", real().positive().withUnit("m"), "between grid points").require();
  cg.option("kernel", choice({"gaussian", "lucy"}), "the kernel").byDefault("gaussian");
  cg.option("grid", regionType(), "{box {lo} {hi}}: the grid's extent");
  cg.option("tag", tagName(), "only the elements carrying this tag");
  cg.option("field",
            choice({"density", "momentum", "velocity", "contactStress", "kineticStress"}),
            "return this array's values");
  cg.option("file", text("file"), "also write the fields as VTK image data (.vti) for ParaView");
  cg.changesScene = false;
  cg.onRanks = OnRanks::Collective;
  cg.run([](Call& c) {
    const auto [s, sel] = scopeOf(c, false);
    const int d = s.dim;
    analysis::CgSpec spec;
    spec.width = c.real("width");
    spec.spacing = c.real("spacing");
    spec.kernel = c.str("kernel") == "lucy" ? analysis::CgKernel::Lucy : analysis::CgKernel::Gaussian;
    if (c.given("grid")) {
      const auto& g = c.get<sim::Region>("grid");
      if (g.kind != sim::Region::Box) c.bad("grid", "must be a box");
      spec.lo = g.lo, spec.hi = g.hi;
    } else {
      const double reach = analysis::kernelCutoff(spec);
      bool first = true;
      for (size_t i = 0; i < s.size(); ++i) {
        if (!sel.hasTag(i)) continue;
        for (int k = 0; k < d; ++k) {
          double lo = s.position[i][k] - s.radius[i] - reach, hi = s.position[i][k] + s.radius[i] + reach;
          spec.lo[k] = first ? lo : std::min(spec.lo[k], lo);
          spec.hi[k] = first ? hi : std::max(spec.hi[k], hi);
        }
        first = false;
      }
    }
    const double points = analysis::cgPointCount(spec, d);
    if (!(points <= kMaxCgPoints))  // also NaN, from a width of Inf
      c.bad("spacing", "makes a grid of " +
                           (points < 1e15 ? std::to_string(int64_t(points)) : formatReal(points)) +
                           " points (at most " +
                           std::to_string(int64_t(kMaxCgPoints)) + ")");
    const analysis::CgField f = analysis::coarseGrain(s, sel, spec);
    if (c.given("file")) {
      const sim::Simulation& scene = session(c).scene();
      togetherOnRanks(scene, [&] {
        if (ranksOf(scene).rank() == 0) {
          writeFileAtomically(c.str("file"), io::vtiBytes(cgImage(f, scene), io::VtkCompression::Fast));
        }
      });
    }
    if (c.given("field")) {
      const analysis::CgArray* a = f.find(c.str("field"));
      return realList(a->values.data(), a->values.size());
    }
    double cell = 1, mass = 0;
    for (int k = 0; k < d; ++k) cell *= f.spacing[k];
    for (double rho : f.find("density")->values) mass += rho * cell;
    Dict arrays;
    for (const analysis::CgArray& a : f.arrays) arrays.emplace_back(a.name, a.components);
    List dims;
    for (int k = 0; k < 3; ++k) dims.emplace_back(f.dims[k]);
    return Value(Dict{{"origin", vecValue(f.origin, 3)},
                      {"spacing", vecValue(f.spacing, 3)},
                      {"dims", dims},
                      {"arrays", arrays},
                      {"mass", mass}});
  });
}

}  // namespace

void registerAnalysisCommands(Registry& r) {
  addStress(r);
  addCoordination(r);
  addFabric(r);
  addPacking(r);
  addMotion(r);
  addCoarseGrain(r);
}

}  // namespace demlab::cmd
