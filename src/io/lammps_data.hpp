// Reading LAMMPS data files of spheres (atom_style sphere, as LAMMPS and LIGGGHTS write them
// with write_data, and as ../shared/bench/data/ holds them), gzip'd or plain.
//
// What is read:
//   - the title line (the first line, always);
//   - the header: "N atoms", "N atom types", "xlo xhi", "ylo yhi", "zlo zhi"; other count lines
//     of the LAMMPS header ("0 bonds", "N extra bond per atom" and the like) are accepted and
//     ignored, since a sphere file has nothing they describe; a tilt line ("xy xz yz") is
//     refused (a triclinic box is not a box of walls);
//   - the Atoms section, one line `id type diameter density x y z` per atom, optionally followed
//     by three integer image flags; a style hint after the keyword ("Atoms # sphere") must say
//     sphere;
//   - the Velocities section when present: `id vx vy vz wx wy wz`;
//   - other sections (Masses, Pair Coeffs, ...) are skipped.
// "#" starts a comment anywhere; blank lines are ignored.
//
// Atoms are returned in file order. Per-atom values are checked as they are read: every
// number finite, diameter and density positive (LAMMPS takes a zero diameter for a point
// particle whose "density" is a mass; demlab has no point particles), type in 1..atom types,
// ids positive and unique, positions inside the closed box. Any failure throws demlab::Error
// with the file name and line number in the message and nothing is returned:
//   IO OPEN, IO READ          the file cannot be opened or read, or its gzip stream is cut short
//   IO FORMAT                 a line that is not what the format allows there
//   IO TRUNCATED              fewer atom (or velocity) lines than the header's count
//   VALUE NUMBER              a field that is not a number, or not finite
//   VALUE DIAMETER / DENSITY / TYPE / ID / POSITION / BOX   a value out of its range
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "core/math.hpp"

namespace demlab::io {

struct SphereData {
  std::string title;          // the first line, without its newline
  std::size_t atomTypes = 0;  // from "N atom types"
  Vec3 boxLo = Vec3::Zero();  // from "xlo xhi", "ylo yhi", "zlo zhi"
  Vec3 boxHi = Vec3::Zero();

  // One entry per atom, in file order.
  std::vector<std::int64_t> ids;
  std::vector<int> types;  // 1-based, as in the file
  std::vector<Real> diameters;
  std::vector<Real> densities;
  std::vector<Vec3> positions;
  std::vector<std::size_t> lines;  // the line of the file each atom was read from
  // Empty when the file has no Velocities section; otherwise one entry per atom, in the order
  // of the atoms above (matched by id).
  std::vector<Vec3> velocities;
  std::vector<Vec3> angularVelocities;

  // Returns the number of atoms.
  std::size_t size() const { return ids.size(); }
};

// Returns the spheres of the LAMMPS data file at `path` (gzip'd or plain, decided from the
// file's first bytes). Changes nothing. Throws demlab::Error as described above.
SphereData readLammpsData(const std::string& path);

// Returns the scene name the benchmarks give a data file: its file name without .gz and .data
// (mono_10k_dense.data.gz -> mono_10k_dense).
std::string sceneName(const std::string& path);

}  // namespace demlab::io
