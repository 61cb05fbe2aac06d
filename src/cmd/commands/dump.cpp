// The "dump" group: the scene written for other tools. VTK XML for ParaView (elements, walls
// and the contact network as .vtp files, now with `dump vtk` or every so many steps or seconds
// with `dump every`, which keeps a .pvd time series per part), CSV of chosen element fields,
// and a LAMMPS data file that `pack file` (and LAMMPS, LIGGGHTS) read back.
#include <algorithm>
#include <cinttypes>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <sstream>

#include "cmd/commands/commands.hpp"
#include "cmd/commands/output_jobs.hpp"
#include "cmd/words.hpp"
#include "core/atomic_file.hpp"
#include "core/interrupt.hpp"
#include "io/vtk_xml.hpp"
#include "output/scene_vtk.hpp"

namespace demlab::cmd {

namespace {

const std::vector<std::string> kParts = {"elements", "walls", "contacts"};
const std::vector<std::string> kCompressions = {"fast", "best", "none"};

// What a VTK dump writes: which parts, compressed how.
struct VtkOptions {
  std::vector<std::string> parts = kParts;
  io::VtkCompression compression = io::VtkCompression::Fast;
};

// A list of part names (each a full name or a unique prefix), in kParts order, no repeats.
PipeType partsType() {
  return custom("list of parts", [](std::string_view w, const Param& p, const Context&) {
    std::vector<std::string> out;
    for (const std::string& word : splitList(w)) {
      const std::string& part = matchChoice(word, kParts, "part", {"VALUE", "PART"});
      if (std::find(out.begin(), out.end(), part) == out.end()) out.push_back(part);
    }
    if (out.empty())
      throw Error("bad " + p.name + " \"\": must name at least one of " + alternatives(kParts, "and"),
                  {"VALUE", "PART"});
    std::vector<std::string> ordered;
    for (const std::string& k : kParts)
      if (std::find(out.begin(), out.end(), k) != out.end()) ordered.push_back(k);
    return std::any(ordered);
  });
}

void vtkOptions(Command& c) {
  c.option("parts", partsType(), "what to write: a list of " + alternatives(kParts, "and"))
      .byDefault("elements walls contacts");
  c.option("compress", choice(kCompressions), "zlib: fast (level 1, run-length matches only), best (level 9), or none")
      .byDefault("fast");
}

VtkOptions readVtkOptions(const Call& c) {
  VtkOptions o;
  o.parts = c.get<std::vector<std::string>>("parts");
  const std::string& k = c.str("compress");
  o.compression = k == "none"   ? io::VtkCompression::None
                  : k == "best" ? io::VtkCompression::Best
                                : io::VtkCompression::Fast;
  return o;
}

// Returns the PolyData of one part of s.
io::VtkPolyData partData(const sim::Simulation& s, const std::string& part) {
  if (part == "elements") return output::elementsVtk(s);
  if (part == "walls") return output::wallsVtk(s);
  return output::contactsVtk(s);
}

// Writes one part of s to PATH.vtp, atomically; returns the file ParaView opens. A distributed
// scene: the walls from rank 0 (their forces summed); the elements and contacts as one piece
// a rank, PATH_rK.vtp, that rank 0's PATH.pvtp lists. Throws IO errors, on every rank when
// one rank's failed (collective in a distributed scene).
std::string writePart(const sim::Simulation& s, const std::string& part, const VtkOptions& o,
                      const std::string& path) {
  if (!s.distributed()) {
    writeFileAtomically(path + ".vtp", io::vtpBytes(partData(s, part), o.compression));
    return path + ".vtp";
  }
  const mpi::Communicator& ranks = ranksOf(s);
  const io::VtkPolyData d = partData(s, part);
  if (part == "walls") {
    togetherOnRanks(s, [&] {
      if (ranks.rank() == 0) writeFileAtomically(path + ".vtp", io::vtpBytes(d, o.compression));
    });
    return path + ".vtp";
  }
  const auto piece = [&](int k) { return path + "_r" + std::to_string(k) + ".vtp"; };
  togetherOnRanks(s, [&] { writeFileAtomically(piece(ranks.rank()), io::vtpBytes(d, o.compression)); });
  togetherOnRanks(s, [&] {
    if (ranks.rank() != 0) return;
    std::vector<std::string> pieces;
    for (int k = 0; k < ranks.size(); ++k) {
      pieces.push_back(std::filesystem::path(piece(k)).filename().string());
    }
    writeFileAtomically(path + ".pvtp", io::pvtpBytes(d, pieces));
  });
  return path + ".pvtp";
}

// Returns the files written: PREFIX_PART.vtp (.pvtp, distributed) per part, each atomically.
// Throws IO errors; a failure leaves the parts already written in place (each file is whole).
std::vector<std::string> writeVtk(const sim::Simulation& s, const VtkOptions& o,
                                  const std::string& prefix) {
  std::vector<std::string> files;
  for (const std::string& part : o.parts) files.push_back(writePart(s, part, o, prefix + "_" + part));
  return files;
}

// One `dump every`: its folder, options and the series so far (one .pvd per part, rewritten
// whole after each frame, so a run stopped at any point leaves a series ParaView opens).
struct Job {
  std::string dir;
  VtkOptions options;
  std::uint64_t frames = 0;
  // Per part, one entry a frame: its time and file (.vtp, or .pvtp when distributed).
  std::vector<std::vector<io::PvdEntry>> series;

  // Writes frame number `frames` of s and the series files (a distributed scene: the frame in
  // pieces, the series from rank 0; collective). Changes frames and series.
  void write(const sim::Simulation& s) {
    char frame[32];
    std::snprintf(frame, sizeof frame, "_%06" PRIu64, frames);
    const std::string prefix = (std::filesystem::path(dir) / "").string();
    series.resize(options.parts.size());
    for (std::size_t k = 0; k < options.parts.size(); ++k) {
      const std::string& part = options.parts[k];
      const std::string file = writePart(s, part, options, prefix + part + frame);
      series[k].push_back({s.time(), std::filesystem::path(file).filename().string(), 0});
    }
    togetherOnRanks(s, [&] {
      if (ranksOf(s).rank() != 0) return;
      for (std::size_t k = 0; k < options.parts.size(); ++k) {
        writeFileAtomically(prefix + options.parts[k] + ".pvd", io::pvdBytes(series[k]));
      }
    });
    ++frames;
  }
};

OutputJobs<Job>& jobs() {
  static OutputJobs<Job> j("dump");
  return j;
}

// The element fields `dump csv` writes: name, and the values of element i from the table.
struct CsvField {
  std::string name;
  std::function<std::string(const sim::ElementTable&, size_t)> value;
};


const std::vector<CsvField>& csvFields() {
  using T = sim::ElementTable;
  auto comp = [](std::vector<double> T::*arr, int width, int k) {
    return [arr, width, k](const T& t, size_t i) { return formatReal((t.*arr)[width * i + k]); };
  };
  static const std::vector<CsvField> f = [&] {
    std::vector<CsvField> v = {
        {"id", [](const T& t, size_t i) { return std::to_string(t.ids[i].scriptId()); }},
        {"material", [](const T& t, size_t i) { return t.materialNames[t.material[i]]; }},
        {"shape", [](const T& t, size_t i) { return t.shapeNames[t.shape[i]]; }},
        {"radius", [](const T& t, size_t i) { return formatReal(t.radius[i]); }},
        {"mass", [](const T& t, size_t i) { return formatReal(t.mass[i]); }},
    };
    const char* axes[] = {"x", "y", "z"};
    const std::pair<const char*, std::vector<double> T::*> vectors[] = {
        {"", &T::position}, {"v", &T::velocity}, {"w", &T::angularVelocity},
        {"f", &T::force},   {"t", &T::torque}};
    for (const auto& [stem, arr] : vectors)
      for (int k = 0; k < 3; ++k) v.push_back({std::string(stem) + axes[k], comp(arr, 3, k)});
    const char* q[] = {"qw", "qx", "qy", "qz"};
    for (int k = 0; k < 4; ++k) v.push_back({q[k], comp(&T::orientation, 4, k)});
    return v;
  }();
  return f;
}

std::vector<std::string> csvFieldNames() {
  std::vector<std::string> n;
  for (const CsvField& f : csvFields()) n.push_back(f.name);
  return n;
}

PipeType csvFieldsType() {
  return custom("list of fields", [](std::string_view w, const Param& p, const Context&) {
    std::vector<std::string> out;
    for (const std::string& word : splitList(w)) {
      const auto names = csvFieldNames();
      if (std::find(names.begin(), names.end(), word) == names.end())
        throw Error("bad field \"" + word + "\" (" + p.name + "): must be " + alternatives(names),
                    {"VALUE", "FIELD"});
      out.push_back(word);
    }
    if (out.empty()) throw Error("bad " + p.name + " \"\": must name a field", {"VALUE", "FIELD"});
    return std::any(out);
  });
}

// Returns the LAMMPS data file of s's balls (atom_style sphere; types are materials in order,
// 1-based): the box is the scene's bounds grown by the largest radius. Throws {VALUE SHAPE}
// when an element is not a ball (the format has no other shape).
std::string lammpsData(const sim::Simulation& s) {
  const sim::ElementTable t = s.elementTable();
  for (uint32_t sh : t.shape)
    if (sh != 0)
      throw Error("can't write a LAMMPS data file: it holds balls only and the scene has " +
                      t.shapeNames[sh] + " elements",
                  {"VALUE", "SHAPE"});
  const size_t n = t.ids.size();
  double rmax = 0;
  for (double r : t.radius) rmax = std::max(rmax, r);
  std::array<sim::Vec3d, 2> b = s.bounds();
  std::ostringstream o;
  o << "demlab scene at time " << formatReal(s.time()) << " (types: materials";
  for (const std::string& m : t.materialNames) o << ' ' << m;
  o << ")\n\n" << n << " atoms\n" << std::max<size_t>(1, t.materialNames.size()) << " atom types\n\n";
  const char* ax[] = {"x", "y", "z"};
  for (int k = 0; k < 3; ++k) {
    double lo = b[0][k] - rmax, hi = b[1][k] + rmax;
    if (!(hi > lo)) lo = -0.5, hi = 0.5;  // a 2D scene's z, or an empty one
    o << formatReal(lo) << ' ' << formatReal(hi) << ' ' << ax[k] << "lo " << ax[k] << "hi\n";
  }
  o << "\nAtoms # sphere\n\n";
  InterruptPoll poll("dump");
  for (size_t i = 0; i < n; ++i) {
    poll();
    const double d = 2 * t.radius[i];
    const double volume = s.dim() == 3 ? M_PI * d * d * d / 6 : M_PI * d * d / 4;
    o << t.ids[i].scriptId() + 1 << ' ' << t.material[i] + 1 << ' ' << formatReal(d) << ' '
      << formatReal(t.mass[i] / volume);
    for (int k = 0; k < 3; ++k) o << ' ' << formatReal(t.position[3 * i + k]);
    o << '\n';
  }
  o << "\nVelocities\n\n";
  for (size_t i = 0; i < n; ++i) {
    poll();
    o << t.ids[i].scriptId() + 1;
    for (int k = 0; k < 3; ++k) o << ' ' << formatReal(t.velocity[3 * i + k]);
    for (int k = 0; k < 3; ++k) o << ' ' << formatReal(t.angularVelocity[3 * i + k]);
    o << '\n';
  }
  return o.str();
}

}  // namespace

void registerDumpCommands(Registry& r) {
  r.describe("dump", "The scene written for other tools: VTK for ParaView, CSV, LAMMPS data.");

  Command& vtk = r.add("dump vtk", "Writes the scene as VTK PolyData files; returns their paths.");
  vtk.interruptible = true;
  vtk.details =
      "Writes PREFIX_elements.vtp (a vertex per element: id, tag_NAME 0/1 per tag, material and "
      "shape indices into the field data's material_names and shape_names, shape_params, "
      "radius, mass, velocity, angular_velocity, force, torque, orientation as a quaternion w x "
      "y z), PREFIX_walls.vtp (wall surfaces, infinite planes drawn across the scene's bounds, "
      "with each wall's id, material and force) and PREFIX_contacts.vtp (a line per contact of "
      "the last step from centre to centre, or to the contact point for a wall: a, b, wall, "
      "force on b, normal, normal_force, tangential_force, overlap). VTK's XML format with "
      "appended binary data, zlib-compressed; each file is replaced atomically. Open them in "
      "ParaView; apply Glyph (sphere, scale by radius, factor 2) to the elements. In a "
      "distributed run each rank writes its elements and the contacts it computed as pieces "
      "PREFIX_elements_rK.vtp and PREFIX_contacts_rK.vtp, listed by PREFIX_elements.pvtp and "
      "PREFIX_contacts.pvtp (the files returned), and rank 0 the walls.";
  vtk.arg("prefix", text("path prefix"), "the files' common start, e.g. out/bed");
  vtkOptions(vtk);
  vtk.changesScene = false;
  vtk.onRanks = OnRanks::Collective;
  vtk.run([](Call& c) {
    List l;
    for (const std::string& f : writeVtk(session(c).scene(), readVtkOptions(c), c.str("prefix")))
      l.emplace_back(f);
    return Value(std::move(l));
  });

  Command& every = r.add("dump every",
                         "Adds a VTK dump output: files every N steps or T seconds and a .pvd "
                         "series per part; returns its id.");
  every.details =
      "Frames go to DIR/elements_000000.vtp, DIR/walls_000000.vtp, DIR/contacts_000000.vtp, "
      "... (the parts asked for) with DIR/elements.pvd etc. listing them with their times: open "
      "the .pvd in ParaView to play the series. Frame 0 is the scene as it is now, written at "
      "once (DIR is created if needed). Runs at the end of each step it is due at, in every "
      "run, until \"dump off\". Contact records are kept only at the steps a dump is due. In a "
      "distributed run the frames are pieces a rank under a .pvtp, as dump vtk writes them, and "
      "rank 0 writes the .pvd.";
  every.option("steps", integer().min(1), "a frame every this many steps");
  every.option("time", real().positive().withUnit("s"), "a frame every this much simulated time");
  every.oneOf({"steps", "time"}, true);
  every.option("dir", text("folder"), "the folder of the frames").byDefault("vtk");
  vtkOptions(every);
  every.run([](Call& c) {
    sim::Simulation& s = session(c).scene();
    auto job = std::make_shared<Job>();
    job->dir = c.str("dir");
    job->options = readVtkOptions(c);
    OutputJobs<Job>::startIn(job->dir, [&] { job->write(s); });
    sim::OutputDef d;
    d.name = "dump " + job->dir;
    if (c.given("steps")) d.everySteps = std::uint64_t(c.integer("steps"));
    if (c.given("time")) d.everyTime = c.real("time");
    d.needsContacts = std::find(job->options.parts.begin(), job->options.parts.end(),
                                "contacts") != job->options.parts.end();
    d.callback = [job](const sim::Simulation& sim) { job->write(sim); };
    d.distributable = true;
    const sim::OutputId id = s.addOutput(d);
    jobs().add(s, id, job);
    return Value(scriptId(id));
  });

  Command& list = r.add("dump list", "Returns the dump outputs as a list of dicts.");
  list.onRanks = OnRanks::Alike;
  list.details = "Each dict: id, dir, parts, steps or time (the interval), frames (written so far).";
  list.changesScene = false;
  list.run([](Call& c) {
    List l;
    for (auto& [info, job] : jobs().of(session(c).scene())) {
      List parts;
      for (const std::string& p : job->options.parts) parts.emplace_back(p);
      Dict d{{"id", scriptId(info.id)}, {"dir", job->dir}, {"parts", parts}};
      if (info.everySteps)
        d.emplace_back("steps", info.everySteps);
      else
        d.emplace_back("time", info.everyTime);
      d.emplace_back("frames", job->frames);
      l.emplace_back(d);
    }
    return Value(std::move(l));
  });

  jobs().declareOff(r);

  Command& csv = r.add("dump csv", "Writes element fields as CSV, a row per element; returns the path.");
  csv.details =
      "A header row of the field names, then a row per element in the scene's order (a "
      "distributed run's: rank 0 writes them in the order of the ids). Numbers "
      "carry the shortest digits that read back exactly. Vectors are split by axis (x y "
      "z, vx vy vz, wx wy wz, fx fy fz, tx ty tz; 2D: z components 0) and the orientation is "
      "a quaternion qw qx qy qz.";
  csv.arg("file", text("file"), "the CSV file");
  csv.option("fields", csvFieldsType(), "the columns, from: " + joinList(csvFieldNames()))
      .byDefault("id material radius mass x y z vx vy vz");
  csv.changesScene = false;
  csv.interruptible = true;
  csv.onRanks = OnRanks::Collective;
  csv.run([](Call& c) {
    const sim::Simulation& s = session(c).scene();
    sim::ElementTable t = s.elementTable();
    // A distributed scene: each rank's rows, under the ids scripts know, written by rank 0 in
    // the order of the ids.
    if (s.distributed()) {
      for (sim::ElementId& id : t.ids) id = s.originalHandle(id);
    }
    std::vector<const CsvField*> cols;
    for (const std::string& name : c.get<std::vector<std::string>>("fields"))
      for (const CsvField& f : csvFields())
        if (f.name == name) cols.push_back(&f);
    std::string out;
    for (size_t k = 0; k < cols.size(); ++k) {
      if (k) out += ',';
      out += cols[k]->name;
    }
    out += '\n';
    InterruptPoll poll("dump");
    std::vector<std::pair<std::int64_t, std::string>> rows;
    for (size_t i = 0; i < t.ids.size(); ++i) {
      poll();
      std::string row;
      for (size_t k = 0; k < cols.size(); ++k) {
        if (k) row += ',';
        row += cols[k]->value(t, i);
      }
      row += '\n';
      if (!s.distributed()) {
        out += row;
      } else {
        rows.emplace_back(scriptId(t.ids[i]), std::move(row));
      }
    }
    if (s.distributed()) {
      // (Each row a line; the id before a tab, for the sort.)
      std::string mine;
      for (const auto& [id, row] : rows) mine += std::to_string(id) + '\t' + row;
      const std::vector<std::vector<char>> parts = ranksOf(s).gatherBytes({mine.begin(), mine.end()});
      rows.clear();
      for (const std::vector<char>& p : parts) {
        for (size_t at = 0; at < p.size();) {
          const size_t tab = size_t(std::find(p.begin() + long(at), p.end(), '\t') - p.begin());
          const size_t end = size_t(std::find(p.begin() + long(tab), p.end(), '\n') - p.begin());
          rows.emplace_back(std::stoll(std::string(p.begin() + long(at), p.begin() + long(tab))),
                            std::string(p.begin() + long(tab) + 1, p.begin() + long(end) + 1));
          at = end + 1;
        }
      }
      std::sort(rows.begin(), rows.end());
      for (const auto& r : rows) out += r.second;
    }
    togetherOnRanks(s, [&] {
      if (ranksOf(s).rank() == 0) writeFileAtomically(c.str("file"), out);
    });
    return Value(c.str("file"));
  });

  Command& data = r.add("dump lammps",
                        "Writes the balls as a LAMMPS data file (atom_style sphere); returns the "
                        "path.");
  data.details =
      "The format `pack file` reads back, as do LAMMPS's and LIGGGHTS's read_data: atom ids are "
      "the element ids plus 1, atom types the materials in creation order (named in the title "
      "line), diameter and density from radius and mass, and a Velocities section with the "
      "angular velocities. The box is the scene's bounds grown by the largest radius. Elements "
      "of other shapes are refused (the format holds balls only). In a distributed run rank 0 "
      "writes the whole scene, gathered as sim save gathers it, its atoms in id order: the "
      "atoms a serial run of the same scene writes, to round-off.";
  data.arg("file", text("file"), "the data file");
  data.changesScene = false;
  data.interruptible = true;
  data.onRanks = OnRanks::Collective;
  data.run([](Call& c) {
    const sim::Simulation& s = session(c).scene();
    if (!s.distributed()) {
      writeFileAtomically(c.str("file"), lammpsData(s));
      return Value(c.str("file"));
    }
    // Rank 0 reads the whole scene back from its gathered checkpoint (the handles scripts
    // hold, the elements in id order) and writes it as a serial scene; a failure is every
    // rank's.
    togetherOnRanks(s, [&] {
      std::vector<std::string> skipped;
      std::string bytes = s.saveBytes(true, &skipped);
      if (ranksOf(s).rank() != 0) return;
      std::unique_ptr<sim::Simulation> whole = sim::makeSimulation(s.dim());
      {
        std::istringstream in(std::move(bytes));
        whole->load(in);
      }
      writeFileAtomically(c.str("file"), lammpsData(*whole));
    });
    return Value(c.str("file"));
  });
}

}  // namespace demlab::cmd
