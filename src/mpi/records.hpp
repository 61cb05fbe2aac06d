// Records of a plain type sent between ranks: the migration of elements to their new owners,
// the copies sent as ghosts (an element may go to several ranks), and gathers of queries.
#pragma once

#include <cstring>
#include <stdexcept>
#include <type_traits>
#include <vector>

#include "mpi/communicator.hpp"

namespace demlab::mpi {

// Returns the bytes of records.
template <class T>
std::vector<char> recordBytes(const std::vector<T>& records) {
  std::vector<char> b(records.size() * sizeof(T));
  if (!b.empty()) std::memcpy(b.data(), records.data(), b.size());
  return b;
}

// Returns the records of every buffer of in, one after another.
template <class T>
std::vector<T> fromRecordBytes(const std::vector<std::vector<char>>& in) {
  size_t n = 0;
  for (const auto& b : in) n += b.size() / sizeof(T);
  std::vector<T> records(n);
  size_t at = 0;
  for (const auto& b : in) {
    if (b.size() % sizeof(T) != 0) throw std::runtime_error("mpi: a record list was cut short");
    if (!b.empty()) std::memcpy(static_cast<void*>(records.data() + at), b.data(), b.size());
    at += b.size() / sizeof(T);
  }
  return records;
}

// Sends out[k] to rank k (out has comm.size() lists) and returns what every rank sent here,
// source rank by source rank, each in its sending order. Collective over comm.
template <class T>
std::vector<T> exchangeRecords(const Communicator& comm, const std::vector<std::vector<T>>& out) {
  static_assert(std::is_trivially_copyable_v<T>);
  if (out.size() != static_cast<size_t>(comm.size())) {
    throw std::invalid_argument("mpi: one record list per rank");
  }
  std::vector<std::vector<char>> bytes(out.size());
  for (size_t k = 0; k < out.size(); ++k) bytes[k] = recordBytes(out[k]);
  return fromRecordBytes<T>(comm.exchange(bytes));
}

// Returns every rank's records, rank by rank, on every rank (each passes its own, of any
// length). Collective over comm.
template <class T>
std::vector<T> gatherRecords(const Communicator& comm, const std::vector<T>& mine) {
  static_assert(std::is_trivially_copyable_v<T>);
  return fromRecordBytes<T>(comm.gatherBytes(recordBytes(mine)));
}

// Returns every rank's records, rank by rank, on rank root; the other ranks get none. For the
// gathers only one rank writes from (a checkpoint): the whole scene held once, not on every
// rank. Collective over comm.
template <class T>
std::vector<T> gatherRecordsTo(const Communicator& comm, const std::vector<T>& mine, int root) {
  std::vector<std::vector<T>> out(static_cast<size_t>(comm.size()));
  out[static_cast<size_t>(root)] = mine;
  return exchangeRecords(comm, out);
}

}  // namespace demlab::mpi
