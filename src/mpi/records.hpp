// Records of a plain type sent between ranks: the migration of elements to their new owners and
// the copies sent as ghosts (an element may go to several ranks).
#pragma once

#include <cstring>
#include <stdexcept>
#include <type_traits>
#include <vector>

#include "mpi/communicator.hpp"

namespace demlab::mpi {

// Sends out[k] to rank k (out has comm.size() lists) and returns what every rank sent here,
// source rank by source rank, each in its sending order. Collective over comm.
template <class T>
std::vector<T> exchangeRecords(const Communicator& comm, const std::vector<std::vector<T>>& out) {
  static_assert(std::is_trivially_copyable_v<T>);
  if (out.size() != static_cast<size_t>(comm.size())) {
    throw std::invalid_argument("mpi: one record list per rank");
  }
  std::vector<std::vector<char>> bytes(out.size());
  for (size_t k = 0; k < out.size(); ++k) {
    bytes[k].resize(out[k].size() * sizeof(T));
    if (!out[k].empty()) std::memcpy(bytes[k].data(), out[k].data(), bytes[k].size());
  }
  const std::vector<std::vector<char>> in = comm.exchange(bytes);
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

}  // namespace demlab::mpi
