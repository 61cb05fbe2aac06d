// The "series" group: time series of named quantities, recorded by an output module every so
// many steps or seconds into memory (and optionally a CSV file, and a status line on the
// terminal, as LAMMPS's thermo output), read back as lists and plotted with gnuplot.
#include <array>
#include <cctype>
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <memory>
#include <optional>

#include <unistd.h>

#include "cmd/commands/commands.hpp"
#include "cmd/commands/output_jobs.hpp"
#include "cmd/words.hpp"
#include "core/atomic_file.hpp"
#include "mpi/communicator.hpp"
#include "sim/boundaries.hpp"

namespace demlab::cmd {

namespace {

using Ledger = sim::EnergyLedger;

// What the quantities of one row read: the scene, and its energy ledger computed once for all
// the energy quantities of the row (a pass over the elements).
struct Row {
  const sim::Simulation& s;
  std::optional<Ledger> ledger;
  const Ledger& energy() {
    if (!ledger) ledger = s.energy();
    return *ledger;
  }
};

// One recorded quantity: its name (the column), SI unit ("" for a pure number), and how to
// read it from the scene at the end of a step.
struct Quantity {
  std::string name, unit;
  std::function<double(Row&)> value;
  bool readsContacts = false;
};

// The quantities every scene has, one row each.
const std::vector<Quantity>& builtins() {
  auto energy = [](double Ledger::*m) {
    return [m](Row& r) { return r.energy().*m; };
  };
  static const std::vector<Quantity> q = {
      {"time", "s", [](Row& r) { return r.s.time(); }},
      {"step", "", [](Row& r) { return double(r.s.stepCount()); }},
      // (A distributed scene: each rank's own elements and contacts, summed.)
      {"elements", "",
       [](Row& r) {
         const sim::Simulation& s = r.s;
         return double(ranksOf(s).sum(std::int64_t(s.distributed() ? s.distribution().owned
                                                                    : s.elementCount())));
       }},
      {"contacts", "",
       [](Row& r) { return double(ranksOf(r.s).sum(std::int64_t(r.s.contactCount()))); }, true},
      {"kinetic", "J", energy(&Ledger::kineticTranslational)},
      {"rotational", "J", energy(&Ledger::kineticRotational)},
      {"gravitational", "J", energy(&Ledger::gravitational)},
      {"elastic", "J", energy(&Ledger::elastic)},
      {"damping", "J", energy(&Ledger::dampingLoss)},
      {"friction", "J", energy(&Ledger::frictionLoss)},
      {"wallwork", "J", energy(&Ledger::wallWork)},
      {"behaviorwork", "J", energy(&Ledger::behaviorWork)},
      {"balance", "J", energy(&Ledger::balance)},
      {"residual", "", energy(&Ledger::residual)},
      {"timestep", "s", [](Row& r) { return r.s.timeStep(); }},
  };
  return q;
}

const std::vector<std::string> kWallParts = {"fx", "fy", "fz", "force", "tx", "ty", "tz", "work"};
const std::vector<std::string> kCounterParts = {"count", "mass", "rate"};

// Returns the quantity inlet:NAME:PART (a source) or sink:NAME:PART (count, mass, or rate: the mass
// per second since it started). The source or sink must exist now (LOOKUP NAME).
Quantity counterQuantity(const std::string& word, const std::string& group, const std::string& name,
                         const std::string& part, const Context& ctx) {
  const std::string& which =
      matchChoice(part, kCounterParts, group + " quantity", {"VALUE", "QUANTITY"});
  const bool sink = group == "sink";
  auto read = [sink, name](const sim::Simulation& s) -> std::array<double, 3> {
    auto pick = [&](const auto& list) -> std::array<double, 3> {
      for (const auto& x : list)
        if (x.name == name) return {double(x.count), x.mass, x.start};
      throw Error("can't find " + std::string(sink ? "sink" : "inlet") + " \"" + name + "\"",
                  {"LOOKUP", "NAME"});
    };
    return sink ? pick(s.sinks()) : pick(s.sources());
  };
  read(session(ctx).scene());  // the lookup's error now, not at the first row
  const std::string unit = which == "count" ? "" : which == "mass" ? "kg" : "kg/s";
  return {word, unit, [read, which](Row& r) {
            const auto c = read(r.s);
            if (which == "count") return c[0];
            if (which == "mass") return c[1];
            const double elapsed = r.s.time() - c[2];
            return elapsed > 0 ? c[1] / elapsed : 0.0;
          }};
}

// Returns the quantity {NAME SCRIPT ?UNIT?}: the value of a Tcl script evaluated at global
// level at each row (during a run only the query and help commands answer it; the others are
// refused while the scene is running). Throws {VALUE QUANTITY} for a name that is not a word.
Quantity scriptQuantity(const std::vector<std::string>& parts, const Param& p, const Context& ctx) {
  const std::string& name = parts[0];
  const bool word = !name.empty() && (std::isalpha(static_cast<unsigned char>(name[0])) || name[0] == '_') &&
                    name.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_.") ==
                        std::string::npos;
  if (!word)
    throw Error("bad quantity name \"" + name + "\" (" + p.name +
                    "): must be a letter or \"_\" then letters, digits, \"_\" or \".\"",
                {"VALUE", "QUANTITY"});
  Session* session = const_cast<Session*>(&cmd::session(ctx));
  const std::string script = "uplevel #0 " + quoteElement(parts[1]);
  return {name, parts.size() == 3 ? parts[2] : "", [session, script, name](Row&) {
            if (!session->evalScript)
              throw Error("series quantity \"" + name + "\" needs a Tcl interpreter", {"STATE", "TCL"});
            const Session::ScriptResult r = session->evalScript(script);
            if (!r.ok)
              throw Error("series quantity \"" + name + "\" failed: " + r.result, {"SERIES", "SCRIPT"});
            double v;
            if (!readReal(r.result, v) || !std::isfinite(v))
              throw Error("series quantity \"" + name + "\" returned \"" + r.result +
                              "\": expected a finite number",
                          {"VALUE", "QUANTITY"});
            return v;
          }};
}

// Returns the force (3), torque (3) and work of wall id on s's elements: in a distributed
// scene every rank's part (its own elements' contacts) summed. Collective there.
std::vector<double> wholeWall(const sim::Simulation& s, sim::WallId id) {
  const sim::WallState w = s.wall(id);
  std::vector<double> v{w.force[0],  w.force[1],  w.force[2], w.torque[0],
                        w.torque[1], w.torque[2], w.work};
  if (s.distributed()) ranksOf(s).sum(v);
  return v;
}

// Returns the quantity `word` names: a builtin, or wall:WALL:PART with WALL a wall's name or
// id and PART fx, fy, fz (the force's components) or force (its magnitude). Throws {VALUE
// QUANTITY} or the wall lookup's error.
Quantity parseQuantity(const std::string& word, const Param& p, const Context& ctx) {
  for (const Quantity& q : builtins())
    if (q.name == word) return q;
  const std::vector<std::string> parts = splitList(word);
  if (parts.size() == 2 || parts.size() == 3) return scriptQuantity(parts, p, ctx);
  if (word.rfind("wall:", 0) == 0) {
    const size_t colon = word.rfind(':');
    const std::string wall = word.substr(5, colon > 5 ? colon - 5 : 0), part = word.substr(colon + 1);
    if (colon <= 5 || wall.empty())
      throw Error("bad quantity \"" + word + "\" (" + p.name + "): must be wall:WALL:PART",
                  {"VALUE", "QUANTITY"});
    const std::string& which = matchChoice(part, kWallParts, "wall quantity", {"VALUE", "QUANTITY"});
    Param wallParam;
    wallParam.name = p.name;
    wallParam.type = wallRef();
    const auto id = std::any_cast<sim::WallId>(convertWord(wall, wallParam, ctx));
    if (which == "work") return {word, "J", [id](Row& r) { return wholeWall(r.s, id)[6]; }};
    if (which[0] == 't') {
      const int axis = which[1] - 'x';
      return {word, "N m", [id, axis](Row& r) { return wholeWall(r.s, id)[3 + axis]; }, true};
    }
    const int axis = which == "fx" ? 0 : which == "fy" ? 1 : which == "fz" ? 2 : -1;
    return {word, "N", [id, axis](Row& r) {
              const std::vector<double> f = wholeWall(r.s, id);
              return axis >= 0 ? f[axis] : std::sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]);
            }};
  }
  for (const std::string group : {"inlet", "sink"}) {
    if (word.rfind(group + ":", 0) != 0) continue;
    const size_t colon = word.rfind(':'), from = group.size() + 1;
    if (colon <= from)
      throw Error("bad quantity \"" + word + "\" (" + p.name + "): must be " + group + ":NAME:PART",
                  {"VALUE", "QUANTITY"});
    return counterQuantity(word, group, word.substr(from, colon - from), word.substr(colon + 1),
                           ctx);
  }
  std::vector<std::string> names;
  for (const Quantity& q : builtins()) names.push_back(q.name);
  names.push_back("wall:WALL:fx|fy|fz|force|tx|ty|tz|work");
  names.push_back("inlet:NAME:count|mass|rate");
  names.push_back("sink:NAME:count|mass|rate");
  names.push_back("{NAME SCRIPT ?UNIT?}");
  throw Error("bad quantity \"" + word + "\" (" + p.name + "): must be " + alternatives(names),
              {"VALUE", "QUANTITY"});
}

PipeType quantitiesType() {
  return custom("list of quantities", [](std::string_view w, const Param& p, const Context& ctx) {
    std::vector<Quantity> out;
    for (const std::string& word : splitList(w)) {
      for (const Quantity& q : out)
        if (q.name == word)
          throw Error("bad quantity \"" + word + "\" (" + p.name + "): named twice",
                      {"VALUE", "QUANTITY"});
      out.push_back(parseQuantity(word, p, ctx));
    }
    if (out.empty())
      throw Error("bad " + p.name + " \"\": must name at least one quantity", {"VALUE", "QUANTITY"});
    return std::any(out);
  });
}


// Returns true on the process that writes a series' file: the first rank of the run's world
// (under mpirun every rank records the rows, before the scene is distributed too, and the
// rows are appended: one rank only may write them).
bool fileWriter() { return mpi::Communicator::world().rank() == 0; }

// One `series every`: its quantities and rows, the CSV it appends to, whether it prints.
struct Job {
  std::vector<Quantity> quantities;
  std::vector<std::vector<double>> rows;
  std::string file;
  bool print = false;

  // Records a row of s: in memory, in the file (a line, flushed, so the file follows the
  // run), on the terminal. Throws {IO WRITE} when the file cannot be appended to. A
  // distributed scene: every rank records the whole scene's row (its quantities gather or sum
  // over the ranks), rank 0 appends it to the file, and a failure is every rank's. Collective
  // there.
  void record(const sim::Simulation& s) {
    std::vector<double> row;
    Row at{s, std::nullopt};
    for (const Quantity& q : quantities) row.push_back(q.value(at));
    if (!file.empty()) {
      togetherOnRanks(s, [&] {
        if (!fileWriter()) return;
        std::ofstream f(file, std::ios::app);
        for (size_t k = 0; k < row.size(); ++k) f << (k ? "," : "") << formatReal(row[k]);
        f << '\n';
        if (!f.flush()) throw Error("error writing \"" + file + "\"", {"IO", "WRITE"});
      });
    }
    if (print) {
      if (rows.empty()) {
        for (const Quantity& q : quantities) std::printf(" %13s", q.name.c_str());
        std::printf("\n");
      }
      for (double v : row) std::printf(" %13.6g", v);
      std::printf("\n");
      std::fflush(stdout);
    }
    rows.push_back(std::move(row));
  }

  // Returns the column of quantity name, or -1.
  int column(const std::string& name) const {
    for (size_t k = 0; k < quantities.size(); ++k)
      if (quantities[k].name == name) return int(k);
    return -1;
  }
};

OutputJobs<Job>& jobs() {
  static OutputJobs<Job> j("series");
  return j;
}

// Returns the job of the series id given as argument "id" of c.
std::shared_ptr<Job> jobOf(Call& c) {
  const auto id = c.get<sim::OutputId>("id");
  for (auto& [info, job] : jobs().of(session(c).scene()))
    if (info.id == id) return job;
  throw Error("no series output", {"LOOKUP", "SERIES"});  // the id type checked it already
}

// Returns the column named by option opt of c in job, or throws {VALUE QUANTITY}.
int columnOption(Call& c, const Job& job, const std::string& opt, const std::string& name) {
  const int k = job.column(name);
  if (k < 0) {
    std::vector<std::string> names;
    for (const Quantity& q : job.quantities) names.push_back(q.name);
    c.bad(opt, "the series records " + alternatives(names, "and") + ", not \"" + name + "\"");
  }
  return k;
}

// Runs gnuplot on script, which writes file + ".tmp", then renames that to file. Throws IO
// GNUPLOT when gnuplot fails or is missing (the temporary file removed; the message ends with
// gnuplot's first complaint), IO WRITE when the rename fails. gnuplot's standard output is
// discarded: where it cannot open the file it writes the PNG there instead.
void runGnuplot(const std::string& script, const std::string& file) {
  char log[] = "/tmp/demlab-gnuplot-XXXXXX";
  const int fd = mkstemp(log);
  if (fd < 0) throw Error("can't make a temporary file for gnuplot's messages", {"IO", "GNUPLOT"});
  close(fd);
  FILE* g = popen(("gnuplot >/dev/null 2>" + std::string(log)).c_str(), "w");
  if (g == nullptr) {
    std::remove(log);
    throw Error("can't run gnuplot", {"IO", "GNUPLOT"});
  }
  std::fwrite(script.data(), 1, script.size(), g);
  const int status = pclose(g);
  std::string complaint;
  {
    std::ifstream said(log);
    // Its errors come as the command echoed, a caret under the fault, then the reason.
    for (std::string line; complaint.empty() && std::getline(said, line);) {
      const size_t start = line.find_first_not_of(" \t^");
      if (start != std::string::npos && line.rfind("gnuplot>", 0) != 0) complaint = line.substr(start);
    }
    // ("line 0: " names the line of its standard input.)
    if (complaint.rfind("line ", 0) == 0 && complaint.find(':') != std::string::npos)
      complaint.erase(0, complaint.find_first_not_of(" \t", complaint.find(':') + 1));
  }
  std::remove(log);
  const std::string tmp = file + ".tmp";
  std::ifstream made(tmp);
  if (status != 0 || !made) {
    std::remove(tmp.c_str());
    throw Error("gnuplot failed to write \"" + file + "\"" +
                    (complaint.empty() ? std::string(" (is gnuplot with pngcairo installed?)")
                                       : ": " + complaint),
                {"IO", "GNUPLOT"});
  }
  if (std::rename(tmp.c_str(), file.c_str()) != 0) {
    std::remove(tmp.c_str());
    throw Error("couldn't rename \"" + tmp + "\" to \"" + file + "\"", {"IO", "WRITE"});
  }
}

// Returns gnuplot's text for s in double quotes.
std::string gnuplotString(const std::string& s) {
  std::string out = "\"";
  for (char ch : s) {
    if (ch == '"' || ch == '\\') out += '\\';
    out += ch;
  }
  return out + "\"";
}

// Returns an axis label: the quantities' names with their units ("kinetic, elastic (J)").
std::string axisLabel(const std::vector<const Quantity*>& qs) {
  std::string names, unit = qs.front()->unit;
  bool oneUnit = true;
  for (const Quantity* q : qs) {
    names += (names.empty() ? "" : ", ") + q->name;
    oneUnit = oneUnit && q->unit == unit;
  }
  if (oneUnit) return unit.empty() ? names : names + " (" + unit + ")";
  std::string mixed;
  for (const Quantity* q : qs) mixed += (mixed.empty() ? "" : ", ") + q->name + (q->unit.empty() ? "" : " (" + q->unit + ")");
  return mixed;
}

}  // namespace

void registerSeriesCommands(Registry& r) {
  r.describe("series", "Time series of named quantities: recorded during runs, read, plotted.");

  Command& every = r.add("series every",
                         "Adds a series output: a row of the quantities every N steps or T "
                         "seconds; returns its id.");
  every.details =
      "Quantities: time (s), step, elements, contacts, the energy ledger's entries (kinetic, "
      "rotational, gravitational, elastic, damping, friction, wallwork, behaviorwork, balance "
      "in J; residual, the run's error indicator), timestep (s), and wall:WALL:fx|fy|fz|force "
      "(the force the elements exert on a wall, by name or id, in N; a removed wall gives "
      "NaN), or {NAME SCRIPT ?UNIT?}: the value of a Tcl script evaluated at global level, e.g. "
      "{szz {lindex [dict get [query stress -region $r] tensor] 8} Pa}; during a run the "
      "script may use the query and help commands only. The first row is the scene now. With -file each row is appended to a CSV file "
      "(a header row first; the file is replaced) as it is recorded; with -print it is also "
      "printed as a line on the terminal (a header line first), as LAMMPS's thermo output. "
      "Recording reads only what the step already computed, except the energies (a pass over "
      "the elements) and contacts (the step keeps its contact records at due steps). In a "
      "distributed run every rank records the whole scene's rows (counts, energies and wall "
      "forces summed over the ranks; a script's queries are collective) and rank 0 writes the "
      "file.";
  every.option("steps", integer().min(1), "a row every this many steps");
  every.option("time", real().positive().withUnit("s"), "a row every this much simulated time");
  every.oneOf({"steps", "time"}, true);
  every.option("quantities", quantitiesType(), "the columns, in order").require();
  every.option("file", text("file"), "a CSV file the rows are appended to");
  every.flag("print", "print each row on the terminal");
  every.onRanks = OnRanks::Collective;
  every.run([](Call& c) {
    sim::Simulation& s = session(c).scene();
    auto job = std::make_shared<Job>();
    job->quantities = c.get<std::vector<Quantity>>("quantities");
    job->print = c.flag("print");
    if (c.given("file")) {
      std::string header;
      for (const Quantity& q : job->quantities) header += (header.empty() ? "" : ",") + q.name;
      togetherOnRanks(s, [&] {
        if (fileWriter()) writeFileAtomically(c.str("file"), header + "\n");
      });
      job->file = c.str("file");
    }
    job->record(s);
    sim::OutputDef d;
    d.name = "series";
    if (c.given("steps")) d.everySteps = std::uint64_t(c.integer("steps"));
    if (c.given("time")) d.everyTime = c.real("time");
    d.needsContacts = false;
    // Every rank records the same rows at the same steps; rank 0 writes the file.
    d.distributable = true;
    for (const Quantity& q : job->quantities) d.needsContacts = d.needsContacts || q.readsContacts;
    d.callback = [job](const sim::Simulation& sim) { job->record(sim); };
    const sim::OutputId id = s.addOutput(d);
    jobs().add(s, id, job);
    return Value(scriptId(id));
  });

  Command& get = r.add("series get", "Returns a series' rows as a dict of columns, or one column.");
  get.arg("id", jobs().ref(), "a series output id");
  get.option("quantity", text("quantity"), "return this column alone");
  get.changesScene = false;
  get.onRanks = OnRanks::Alike;  // (every rank records the whole scene's rows)
  get.run([](Call& c) {
    const auto job = jobOf(c);
    auto column = [&](size_t k) {
      List l;
      for (const auto& row : job->rows) l.emplace_back(row[k]);
      return l;
    };
    if (c.given("quantity")) return Value(column(size_t(columnOption(c, *job, "quantity", c.str("quantity")))));
    Dict d;
    for (size_t k = 0; k < job->quantities.size(); ++k) d.emplace_back(job->quantities[k].name, column(k));
    return Value(d);
  });

  Command& list = r.add("series list", "Returns the series outputs as a list of dicts.");
  list.details = "Each dict: id, quantities, steps or time (the interval), rows, file.";
  list.changesScene = false;
  list.onRanks = OnRanks::Alike;
  list.run([](Call& c) {
    List l;
    for (auto& [info, job] : jobs().of(session(c).scene())) {
      List names;
      for (const Quantity& q : job->quantities) names.emplace_back(q.name);
      Dict d{{"id", scriptId(info.id)}, {"quantities", names}};
      if (info.everySteps)
        d.emplace_back("steps", info.everySteps);
      else
        d.emplace_back("time", info.everyTime);
      d.emplace_back("rows", job->rows.size());
      d.emplace_back("file", job->file);
      l.emplace_back(d);
    }
    return Value(std::move(l));
  });

  jobs().declareOff(r);

  Command& plot = r.add("series plot", "Plots quantities of a series against another into a PNG file with gnuplot; returns the path.");
  plot.details =
      "Axis labels carry the quantities' units. The y quantities share one axis; -logy makes "
      "it logarithmic (values <= 0 are then left out by gnuplot). Needs gnuplot with the "
      "pngcairo terminal (Debian's gnuplot-nox). In a distributed run rank 0 draws the rows every "
      "rank holds; a failure is every rank's.";
  plot.arg("id", jobs().ref(), "a series output id");
  plot.option("file", text("file"), "the PNG file").require();
  plot.option("x", text("quantity"), "the abscissa").byDefault("time");
  plot.option("y", text("quantities").asList(), "the quantities plotted (a list)").require();
  plot.option("title", text("text"), "a title above the plot");
  plot.option("size", ints(), "{width height} in pixels").byDefault("800 500");
  plot.flag("logy", "a logarithmic y axis");
  plot.changesScene = false;
  plot.onRanks = OnRanks::Collective;
  plot.run([](Call& c) {
    const auto job = jobOf(c);
    const std::string file = c.str("file");
    if (file.size() < 4 || file.substr(file.size() - 4) != ".png")
      c.bad("file", "must end in .png (gnuplot writes PNG)");
    const auto& size = c.get<std::vector<std::int64_t>>("size");
    if (size.size() != 2 || size[0] < 64 || size[1] < 64 || size[0] > 8192 || size[1] > 8192)
      c.bad("size", "must be {width height}, each 64 to 8192");
    const int x = columnOption(c, *job, "x", c.str("x"));
    std::vector<int> ys;
    std::vector<const Quantity*> yq;
    for (const std::string& name : splitList(c.str("y"))) {
      ys.push_back(columnOption(c, *job, "y", name));
      yq.push_back(&job->quantities[size_t(ys.back())]);
    }
    if (ys.empty()) c.bad("y", "must name at least one quantity");
    if (job->rows.empty()) throw Error("the series has no rows to plot", {"STATE", "EMPTY"});
    std::string script = "set terminal pngcairo size " + std::to_string(size[0]) + "," +
                         std::to_string(size[1]) + " enhanced font \"DejaVu Sans,11\"\n";
    script += "set output " + gnuplotString(file + ".tmp") + "\nset grid\nset key top right\n";
    script += "set xlabel " + gnuplotString(axisLabel({&job->quantities[size_t(x)]})) + " noenhanced\n";
    script += "set ylabel " + gnuplotString(axisLabel(yq)) + " noenhanced\n";
    if (c.given("title")) script += "set title " + gnuplotString(c.str("title")) + " noenhanced\n";
    script += "set format y \"%g\"\nset format x \"%g\"\n";
    if (c.flag("logy")) script += "set logscale y\n";
    script += "plot ";
    for (size_t k = 0; k < ys.size(); ++k) {
      script += std::string(k ? ", " : "") + "'-' using 1:2 with linespoints pt 7 ps 0.4 title " +
                gnuplotString(yq[k]->name) + " noenhanced";
    }
    script += "\n";
    for (size_t k = 0; k < ys.size(); ++k) {
      for (const auto& row : job->rows)
        script += formatReal(row[size_t(x)]) + ' ' + formatReal(row[size_t(ys[k])]) + '\n';
      script += "e\n";
    }
    // Every rank holds the same rows; the world's rank 0 draws, and its failure is every rank's.
    togetherOnRanks(session(c).scene(), [&] {
      if (fileWriter()) runGnuplot(script, file);
    });
    return Value(file);
  });
}

}  // namespace demlab::cmd
