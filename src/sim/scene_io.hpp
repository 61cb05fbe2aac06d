// The binary form of a whole scene: the checkpoint format (save/load), the bytes the state
// digest hashes, and the carrier of clone(). Everything that determines the scene's future is
// written, including what a fresh start would recompute differently: the neighbor candidates
// and skin bookkeeping (their order fixes the order forces are summed in), the pair histories
// in the table's iteration order (re-inserted into a table of the same size they rebuild the
// same layout), the handle pools (future handles), the forces of the last step (the next
// step's first kick).
//
// Format: "DEMLABCK", u32 version, u32 dimension, then the sections in the order of
// writeScene. Numbers are little-endian as the machine stores them (x86-64 and aarch64 both
// are); doubles are copied bit for bit.
#pragma once

#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>
#include <vector>

#include "core/error.hpp"
#include "core/interrupt.hpp"
#include "sim/scene.hpp"

namespace demlab::sim {

// Ctrl-C is polled every kPollBytes written or read (core/interrupt.hpp): a checkpoint, a clone
// or a digest of a scene of millions of grains and bonds takes a second. The commands that
// serialize build a new copy or read into a new scene, so stopping part way changes nothing.
inline constexpr size_t kPollBytes = kPollSliceBytes;

inline constexpr uint32_t kFormatVersion = 3;  // 3: the springs' drift velocities, dampers
inline constexpr uint32_t kOldestFormatVersion = 2;  // 2: the Coulomb criterion

class Writer {
 public:
  std::string bytes;
  template <class T>
  void raw(const T& x) {
    static_assert(std::is_trivially_copyable_v<T>);
    bytes.append(reinterpret_cast<const char*>(&x), sizeof(T));
    if (bytes.size() >= nextPoll_) {
      nextPoll_ = bytes.size() + kPollBytes;
      pollInterrupt("serializing the scene");
    }
  }
  void u8(uint8_t x) { raw(x); }
  void u32(uint32_t x) { raw(x); }
  void u64(uint64_t x) { raw(x); }
  void f64(double x) { raw(x); }
  void str(const std::string& s) {
    u64(s.size());
    bytes.append(s);
  }
  template <int D>
  void vec(const VecD<D>& v) {
    for (int k = 0; k < D; ++k) f64(v[k]);
  }
  void ang(Real w) { f64(w); }
  void ang(const Vec3& w) { vec<3>(w); }
  void rot(const Rotation2& r) { f64(r.angle); }
  void rot(const Quat& q) {
    f64(q.w());
    f64(q.x());
    f64(q.y());
    f64(q.z());
  }
  template <class T, class F>
  void list(const std::vector<T>& v, F&& each) {
    u64(v.size());
    for (const T& x : v) each(x);
  }
  // Starts a section that says its length (tag, u64 byte count, body) written in place: returns
  // where its count goes, for endSection. A large body written into a Writer of its own and
  // then appended was copied once more, in one call Ctrl-C could not stop.
  size_t beginSection(const char* tag) {
    bytes.append(tag, 4);
    const size_t at = bytes.size();
    u64(0);
    return at;
  }
  // Ends the section begun at `at`: writes its body's length there.
  void endSection(size_t at) {
    const uint64_t n = bytes.size() - at - sizeof(uint64_t);
    std::memcpy(bytes.data() + at, &n, sizeof n);
  }

 private:
  size_t nextPoll_ = kPollBytes;
};

class Reader {
 public:
  // Reads b, which must outlive the Reader.
  explicit Reader(std::string_view b) : bytes_(b) {}
  template <class T>
  T raw() {
    static_assert(std::is_trivially_copyable_v<T>);
    if (pos_ + sizeof(T) > bytes_.size()) bad("truncated");
    T x;
    std::memcpy(&x, bytes_.data() + pos_, sizeof(T));
    pos_ += sizeof(T);
    if (pos_ >= nextPoll_) {
      nextPoll_ = pos_ + kPollBytes;
      pollInterrupt("reading the scene");
    }
    return x;
  }
  uint8_t u8() { return raw<uint8_t>(); }
  uint32_t u32() { return raw<uint32_t>(); }
  uint64_t u64() { return raw<uint64_t>(); }
  double f64() { return raw<double>(); }
  // Returns a count n, checking that n items of at least minBytes each can still follow.
  size_t count(size_t minBytes) {
    const uint64_t n = u64();
    if (minBytes > 0 && n > (bytes_.size() - pos_) / minBytes) bad("truncated");
    return static_cast<size_t>(n);
  }
  std::string str() {
    const size_t n = count(1);
    std::string s(bytes_.substr(pos_, n));
    pos_ += n;
    return s;
  }
  template <int D>
  VecD<D> vec() {
    VecD<D> v;
    for (int k = 0; k < D; ++k) v[k] = f64();
    return v;
  }
  template <class A>
  A ang() {
    if constexpr (std::is_same_v<A, Real>) {
      return f64();
    } else {
      return vec<3>();
    }
  }
  template <class R>
  R rot() {
    if constexpr (std::is_same_v<R, Rotation2>) {
      return Rotation2{f64()};
    } else {
      const double w = f64(), x = f64(), y = f64(), z = f64();
      return Quat(w, x, y, z);
    }
  }
  bool atEnd() const { return pos_ == bytes_.size(); }
  // Returns the bytes not read yet.
  size_t remaining() const { return bytes_.size() - pos_; }
  // Returns the next n bytes (n from count(1), so they are there) and moves past them. A view
  // in place, not a copy: a section is read by a Reader of its own (a bond section of hundreds
  // of megabytes took a tenth of a second to copy).
  std::string_view bytesOf(size_t n) {
    if (n > bytes_.size() - pos_) bad("truncated");
    const std::string_view out = bytes_.substr(pos_, n);
    pos_ += n;
    return out;
  }
  [[noreturn]] static void bad(const std::string& why) {
    throw Error("bad checkpoint: " + why, {"LOAD", "FORMAT"});
  }
  // The format version of the bytes (the header's; a section's Reader is given it).
  uint32_t version = kFormatVersion;

 private:
  std::string_view bytes_;
  size_t pos_ = 0;
  size_t nextPoll_ = kPollBytes;
};

// What the bytes are for: a checkpoint (TimeFunctions must be absent), the digest (a
// TimeFunction is written as a flag), or a clone (flags; the caller copies the functions).
enum class IoMode { Checkpoint, Digest, Clone };

inline constexpr char kMagic[9] = "DEMLABCK";
// Starts the optional last section (the watchdog's options when not the defaults).
inline constexpr char kWatchdogTag[5] = "WDOG";
// Starts the optional section after it: the touch correction, when on (sim/touch.hpp).
inline constexpr char kTouchTag[5] = "TUCH";
// Follows them when Hertz-Mindlin's damping is calibrated. Absent: LIGGGHTS's damping, what
// every checkpoint written before the choice existed ran with, so such a file resumes with
// the physics it was saved with (and a scene set to liggghts keeps its old bytes and digest).
inline constexpr char kDampingTag[5] = "HCAL";
// After those, sections that say their length: a 4-character tag, a u64 byte count, the bytes.
// A reader meets only known tags (a checkpoint of a later demlab with a section this one does
// not know is refused by name, never read as garbage); each is written only when the scene
// has what it holds, so a scene without it has the bytes (and the digest) it had before.
// The blocked degrees of freedom (sim/constraints.hpp): u64 count, then per element its
// handle (u32 index, u32 generation) and u8 dof mask.
inline constexpr char kBlockedTag[5] = "BLKD";
// The materials' cohesion (sim/cohesion.hpp), when one has any: u64 count (the materials'),
// then one f64 each, in material order.
inline constexpr char kCohesionTag[5] = "COHE";
// The pairs' own coefficients (Scene::pairOverrides), when any: u64 count, then per pair u32 a,
// u32 b (material indices, a <= b) and f64 restitution, friction, rolling, cohesion (NaN: unset).
inline constexpr char kPairTag[5] = "PAIR";
// The pairs' own effective moduli, when one has any: u64 count (the PAIR section's), then one
// f64 each in the PAIR section's order (NaN: the mixing rule's). Written after PAIR.
inline constexpr char kPairYoungTag[5] = "PYNG";
// The element shapes (sim/shape.hpp), written only when some Geometry beyond the ball's exists:
// the Geometry table by shape type name and parameters, each element's Geometry index, the
// shape candidate pairs, and the tangential springs of the shape contact points.
inline constexpr char kShapeTag[5] = "SHAP";
// The bonds (sim/bond.hpp), written only when the scene has a bond model, a bond or a break
// (sim/bond_io.cpp has the layout).
inline constexpr char kBondTag[5] = "BOND";
// The sources (sim/source.hpp), when any: their Defs, counters and generators' states.
inline constexpr char kSourceTag[5] = "SRCE";
// The sources' and sinks' intervals (SourceDef::every, SinkDef::every), when one is not 1.
inline constexpr char kEveryTag[5] = "EVRY";
// The contact critical step (Scene::contactStep), when the scene has one.
inline constexpr char kContactStepTag[5] = "CSTP";
// The automatic step's motion bound (Scene::stepsPerContact, motionStep, motionSpeed: three
// f64), when one of them differs from a new scene's.
inline constexpr char kMotionStepTag[5] = "MSTP";
// Which sources turn their elements at random (SourceDef::randomOrientation), when one does:
// u64 count (the sources'), then a u8 each. Written after SRCE.
inline constexpr char kSourceOrientationTag[5] = "SORI";
inline constexpr char kSourceShapeTag[5] = "SSHP";
// The sinks (sim/sink.hpp), when any: their Defs and counters.
inline constexpr char kSinkTag[5] = "SINK";
inline constexpr char kPeriodicTag[5] = "PERI";  // periodic cell (sim/periodic.hpp)
// The walls' state beyond the fixed wall record, when a wall has any: per wall its work, the
// rotation turned before its last change of motion, and its servo.
inline constexpr char kWallExtraTag[5] = "WALX";
// The holes of finite walls (physics::FlatWallShape::hole), when a wall has one: u64 count (the
// walls'), then per wall in dense order f64 its hole (0: none; only a finite wall has one).
inline constexpr char kWallHoleTag[5] = "HOLE";
// The grains' margin weights at the last search (Scene::marginWeight), when any: u64 count (the
// positions at the search's), then one f64 each.
inline constexpr char kMarginTag[5] = "MRGN";
// With the touch correction on, after a step: the candidates' touch states of that step (what
// the touch module compares the next step's with): u8 flags (1: the grain pairs', 2: the
// walls'), then with flag 1 Scene::touchNow (u64 count, the candidates', then one u8 each:
// kernel::kTouching, kCutOff bits), with flag 2 Scene::wallTouchNow (u64 walls, then per wall
// its candidates' count and states).
inline constexpr char kTouchStateTag[5] = "TSTA";
// The digest's only (never in a checkpoint or a clone's bytes): which walls' motion components
// are scripted, and the angle each turned since the last search.
inline constexpr char kScriptedWallTag[5] = "SCRW";
// What edits placed since the last step (Scene::placedElements, placedWalls), when anything:
// u64 count, per element its handle (u32 index, u32 generation); the same for the walls.
inline constexpr char kPlacedTag[5] = "PLCD";
// The elements' global ids (ElementArrays::globalId), when one differs from its slot or the
// next id from the slot count (after a removal and an addition): u64 the next id, then u64
// count (the elements'), then one u64 each in dense order. Without it, each id is its slot.
inline constexpr char kGlobalIdTag[5] = "GIDS";

// Appends the whole scene to w, with `behaviors` in place of the scene's own when given (a
// checkpoint that leaves out the behaviors holding TimeFunctions). Changes nothing else.
template <int D>
void writeScene(Writer& w, const Scene<D>& s, IoMode mode,
                const BehaviorManager<D>* behaviors = nullptr);

// Returns a 64-bit hash of b: FNV-1a, eight bytes per round for speed. It tells scenes apart
// (the state digest) and finds damaged files; it does not resist an adversary.
uint64_t hashBytes(std::string_view b);

// A checkpoint file is the scene's bytes, then "CHECKSUM" and hashBytes of those bytes, so a
// file damaged anywhere (a flipped bit, a truncation) fails to load instead of loading changed.
// Returns the file's bytes for the scene's.
std::string sealCheckpoint(std::string sceneBytes);
// Returns the scene's bytes of a checkpoint file. Throws {LOAD FORMAT} when the file does not
// end in a checksum or the checksum does not match.
std::string unsealCheckpoint(std::string fileBytes);

// Reads a whole scene written by writeScene into s (a fresh Scene). Throws {LOAD FORMAT} on
// malformed input and {LOAD DIMENSION} for a checkpoint of the other dimension; s is then
// garbage and must be dropped by the caller.
template <int D>
void readScene(Reader& r, Scene<D>& s);

// Appends the bonds' section body to w; reads it back into s, whose elements are already
// read (sim/bond_io.cpp). readBonds throws {LOAD FORMAT} on malformed input.
template <int D>
void writeBonds(Writer& w, const Scene<D>& s);
template <int D>
void readBonds(Reader& r, Scene<D>& s);

}  // namespace demlab::sim
