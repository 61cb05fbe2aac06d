#include "mpi/communicator.hpp"

#include <algorithm>
#include <chrono>
#include <thread>
#include <climits>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>

#ifdef DEMLAB_HAVE_MPI
#include <mpi.h>
#endif

namespace demlab::mpi {

#ifdef DEMLAB_HAVE_MPI
namespace {
// The ranks' agreement on how a script ended (Session::endScript), apart from the world.
MPI_Comm endingComm = MPI_COMM_NULL;
}  // namespace
#endif

bool built() {
#ifdef DEMLAB_HAVE_MPI
  return true;
#else
  return false;
#endif
}

bool launched() {
  return std::getenv("OMPI_COMM_WORLD_SIZE") != nullptr || std::getenv("PMI_SIZE") != nullptr;
}

namespace {

// Returns the number of ranks the launcher's environment names, or 0 when it names none.
long launchedRanks() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE"}) {
    if (const char* v = std::getenv(name)) return std::strtol(v, nullptr, 10);
  }
  return 0;
}

}  // namespace

Session::Session(int* argc, char*** argv) {
#ifdef DEMLAB_HAVE_MPI
  // (One rank runs as a process started alone: MPI would add its start-up and nothing else.)
  if (launchedRanks() < 2) return;
  int up = 0;
  MPI_Initialized(&up);
  if (up) return;
  MPI_Init(argc, argv);
  MPI_Comm_dup(MPI_COMM_WORLD, &endingComm);
  started_ = true;
#else
  (void)argc;
  (void)argv;
#endif
}

Session::~Session() {
#ifdef DEMLAB_HAVE_MPI
  if (started_) {
    if (endingComm != MPI_COMM_NULL) MPI_Comm_free(&endingComm);
    MPI_Finalize();
  }
#endif
}

Session::Ending Session::endScript(int status, double patience,
                                   const std::string& lastWords) const {
  Ending e;
  e.worst = status;
  e.firstFailed = status != 0 ? 0 : -1;
#ifdef DEMLAB_HAVE_MPI
  if (!started_) return e;
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  if (size == 1) return e;
  // The reduction goes over a communicator of its own: a rank still inside a step's collective
  // on the world must not have it matched with this one.
  int mine[2] = {status, status != 0 ? size - rank : 0}, all[2] = {0, 0};
  MPI_Request request;
  MPI_Iallreduce(mine, all, 2, MPI_INT, MPI_MAX, endingComm, &request);
  const double start = MPI_Wtime();
  for (;;) {
    int done = 0;
    MPI_Test(&request, &done, MPI_STATUS_IGNORE);
    if (done) break;
    if (status != 0 && MPI_Wtime() - start > patience) {
      std::fprintf(stderr, "%s\n", lastWords.c_str());
      std::fflush(stderr);
      MPI_Abort(MPI_COMM_WORLD, status);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  e.worst = all[0];
  e.firstFailed = all[1] > 0 ? size - all[1] : -1;
#else
  (void)patience;
  (void)lastWords;
#endif
  return e;
}

Communicator& Communicator::world() {
  static Communicator world = [] {
#ifdef DEMLAB_HAVE_MPI
    int up = 0;
    MPI_Initialized(&up);
    if (up) {
      int rank = 0, size = 1;
      MPI_Comm_rank(MPI_COMM_WORLD, &rank);
      MPI_Comm_size(MPI_COMM_WORLD, &size);
      return Communicator(rank, size, true);
    }
#endif
    return Communicator(0, 1, false);
  }();
  return world;
}

Communicator& Communicator::self() {
  static Communicator one(0, 1, false);
  return one;
}

#ifdef DEMLAB_HAVE_MPI
namespace {

// Returns n as an MPI count, or throws if it does not fit.
int countOf(size_t n) {
  if (n > static_cast<size_t>(INT_MAX)) throw std::length_error("mpi: message over 2 GiB");
  return static_cast<int>(n);
}

template <class T>
void allreduce(std::vector<T>& values, MPI_Datatype type, MPI_Op op) {
  MPI_Allreduce(MPI_IN_PLACE, values.data(), countOf(values.size()), type, op, MPI_COMM_WORLD);
}

}  // namespace
#endif

void Communicator::sum(std::vector<double>& values) const {
  if (!world_ || size_ == 1) return;
#ifdef DEMLAB_HAVE_MPI
  // Gathered to rank 0 and added there in rank order, then broadcast: MPI_Allreduce may add in
  // any order, and a run must not depend on how the library reduces.
  const size_t n = values.size();
  std::vector<double> all(rank_ == 0 ? n * static_cast<size_t>(size_) : 0);
  MPI_Gather(values.data(), countOf(n), MPI_DOUBLE, all.data(), countOf(n), MPI_DOUBLE, 0,
             MPI_COMM_WORLD);
  if (rank_ == 0) {
    for (size_t i = 0; i < n; ++i) {
      double s = all[i];
      for (int r = 1; r < size_; ++r) s += all[static_cast<size_t>(r) * n + i];
      values[i] = s;
    }
  }
  MPI_Bcast(values.data(), countOf(n), MPI_DOUBLE, 0, MPI_COMM_WORLD);
#endif
}

void Communicator::sum(std::vector<int64_t>& values) const {
  if (!world_ || size_ == 1) return;
#ifdef DEMLAB_HAVE_MPI
  allreduce(values, MPI_INT64_T, MPI_SUM);
#endif
}

void Communicator::max(std::vector<double>& values) const {
  if (!world_ || size_ == 1) return;
#ifdef DEMLAB_HAVE_MPI
  allreduce(values, MPI_DOUBLE, MPI_MAX);
#endif
}

void Communicator::min(std::vector<double>& values) const {
  if (!world_ || size_ == 1) return;
#ifdef DEMLAB_HAVE_MPI
  allreduce(values, MPI_DOUBLE, MPI_MIN);
#endif
}

namespace {

// Returns reduce applied to the one value v (as a vector of one).
template <class T, class Reduce>
T reduceOne(T v, Reduce&& reduce) {
  std::vector<T> one{v};
  reduce(one);
  return one[0];
}

}  // namespace

double Communicator::sum(double v) const {
  return reduceOne(v, [this](std::vector<double>& x) { sum(x); });
}

int64_t Communicator::sum(int64_t v) const {
  return reduceOne(v, [this](std::vector<int64_t>& x) { sum(x); });
}

double Communicator::max(double v) const {
  return reduceOne(v, [this](std::vector<double>& x) { max(x); });
}

double Communicator::min(double v) const {
  return reduceOne(v, [this](std::vector<double>& x) { min(x); });
}

std::vector<double> Communicator::gather(const std::vector<double>& values) const {
  if (!world_ || size_ == 1) return values;
  std::vector<double> all(values.size() * static_cast<size_t>(size_));
#ifdef DEMLAB_HAVE_MPI
  MPI_Allgather(values.data(), countOf(values.size()), MPI_DOUBLE, all.data(),
                countOf(values.size()), MPI_DOUBLE, MPI_COMM_WORLD);
#endif
  return all;
}

std::vector<std::vector<char>> Communicator::gatherBytes(const std::vector<char>& mine) const {
  if (!world_ || size_ == 1) return {mine};
  const size_t p = static_cast<size_t>(size_);
  std::vector<std::vector<char>> all(p);
#ifdef DEMLAB_HAVE_MPI
  const int n = countOf(mine.size());
  std::vector<int> count(p), at(p);
  MPI_Allgather(&n, 1, MPI_INT, count.data(), 1, MPI_INT, MPI_COMM_WORLD);
  size_t total = 0;
  for (size_t k = 0; k < p; ++k) {
    at[k] = countOf(total);
    total += static_cast<size_t>(count[k]);
  }
  std::vector<char> joined(total);
  MPI_Allgatherv(mine.data(), n, MPI_BYTE, joined.data(), count.data(), at.data(), MPI_BYTE,
                 MPI_COMM_WORLD);
  for (size_t k = 0; k < p; ++k) {
    all[k].assign(joined.begin() + at[k], joined.begin() + at[k] + count[k]);
  }
#endif
  return all;
}

std::vector<std::vector<char>> Communicator::exchange(
    const std::vector<std::vector<char>>& out) const {
  if (out.size() != static_cast<size_t>(size_)) {
    throw std::invalid_argument("mpi: exchange needs one buffer per rank");
  }
  if (!world_ || size_ == 1) return out;
  std::vector<std::vector<char>> in(static_cast<size_t>(size_));
#ifdef DEMLAB_HAVE_MPI
  const size_t p = static_cast<size_t>(size_);
  std::vector<int> sendCount(p), recvCount(p), sendAt(p), recvAt(p);
  for (size_t k = 0; k < p; ++k) sendCount[k] = countOf(out[k].size());
  MPI_Alltoall(sendCount.data(), 1, MPI_INT, recvCount.data(), 1, MPI_INT, MPI_COMM_WORLD);
  size_t sendTotal = 0, recvTotal = 0;
  for (size_t k = 0; k < p; ++k) {
    sendAt[k] = countOf(sendTotal);
    recvAt[k] = countOf(recvTotal);
    sendTotal += static_cast<size_t>(sendCount[k]);
    recvTotal += static_cast<size_t>(recvCount[k]);
  }
  std::vector<char> send(sendTotal), recv(recvTotal);
  for (size_t k = 0; k < p; ++k) {
    std::copy(out[k].begin(), out[k].end(), send.begin() + sendAt[k]);
  }
  MPI_Alltoallv(send.data(), sendCount.data(), sendAt.data(), MPI_BYTE, recv.data(),
                recvCount.data(), recvAt.data(), MPI_BYTE, MPI_COMM_WORLD);
  for (size_t k = 0; k < p; ++k) {
    in[k].assign(recv.begin() + recvAt[k], recv.begin() + recvAt[k] + recvCount[k]);
  }
#endif
  return in;
}

void Communicator::exchangeWith(const std::vector<int>& to,
                                const std::vector<std::vector<char>>& out,
                                const std::vector<int>& from,
                                std::vector<std::vector<char>>& in) const {
  if (to.size() != out.size() || from.size() != in.size()) {
    throw std::invalid_argument("mpi: one buffer per rank named");
  }
  if (!world_ || size_ == 1) {
    // One rank: whatever it sends to itself is what it receives.
    for (size_t j = 0; j < from.size(); ++j) {
      for (size_t i = 0; i < to.size(); ++i) {
        if (to[i] == from[j]) in[j] = out[i];
      }
    }
    return;
  }
#ifdef DEMLAB_HAVE_MPI
  std::vector<MPI_Request> requests(to.size() + from.size());
  for (size_t j = 0; j < from.size(); ++j) {
    MPI_Irecv(in[j].data(), countOf(in[j].size()), MPI_BYTE, from[j], 0, MPI_COMM_WORLD,
              &requests[j]);
  }
  for (size_t i = 0; i < to.size(); ++i) {
    MPI_Isend(out[i].data(), countOf(out[i].size()), MPI_BYTE, to[i], 0, MPI_COMM_WORLD,
              &requests[from.size() + i]);
  }
  MPI_Waitall(static_cast<int>(requests.size()), requests.data(), MPI_STATUSES_IGNORE);
#endif
}

struct PostedExchange::Requests {
#ifdef DEMLAB_HAVE_MPI
  std::vector<MPI_Request> receives, sends;
#endif
};

PostedExchange::PostedExchange() : pending_(std::make_unique<Requests>()) {}

PostedExchange::~PostedExchange() {
#ifdef DEMLAB_HAVE_MPI
  int ended = 0;
  MPI_Finalized(&ended);
  if (ended) return;  // (MPI has ended every request with itself)
  // A receive still posted (a step left between its halves) is cancelled, as the buffer goes;
  // the sends are waited for (every rank receives its messages in the step that sent them).
  for (MPI_Request& q : pending_->receives) {
    MPI_Cancel(&q);
    MPI_Wait(&q, MPI_STATUS_IGNORE);
  }
  pending_->receives.clear();
#endif
  finishSends();
}

void PostedExchange::post(const Communicator& comm, const std::vector<int>& to,
                          const std::vector<std::vector<char>>& out,
                          const std::vector<int>& from, std::vector<std::vector<char>>& in) {
  finishSends();
  if (!comm.world_ || comm.size_ == 1) {
    comm.exchangeWith(to, out, from, in);
    return;
  }
#ifdef DEMLAB_HAVE_MPI
  if (to.size() != out.size() || from.size() != in.size()) {
    throw std::invalid_argument("mpi: one buffer per rank named");
  }
  receive();
  Requests& r = *pending_;
  r.receives.resize(from.size());
  for (size_t j = 0; j < from.size(); ++j) {
    MPI_Irecv(in[j].data(), countOf(in[j].size()), MPI_BYTE, from[j], 0, MPI_COMM_WORLD,
              &r.receives[j]);
  }
  r.sends.resize(to.size());
  for (size_t i = 0; i < to.size(); ++i) {
    MPI_Isend(out[i].data(), countOf(out[i].size()), MPI_BYTE, to[i], 0, MPI_COMM_WORLD,
              &r.sends[i]);
  }
#endif
}

#ifdef DEMLAB_HAVE_MPI
namespace {
// Waits for every request of q, then empties it.
void waitAll(std::vector<MPI_Request>& q) {
  if (!q.empty()) MPI_Waitall(static_cast<int>(q.size()), q.data(), MPI_STATUSES_IGNORE);
  q.clear();
}
}  // namespace
#endif

void PostedExchange::receive() {
#ifdef DEMLAB_HAVE_MPI
  waitAll(pending_->receives);
#endif
}

void PostedExchange::finishSends() {
#ifdef DEMLAB_HAVE_MPI
  waitAll(pending_->sends);
#endif
}

void Communicator::barrier() const {
  if (!world_ || size_ == 1) return;
#ifdef DEMLAB_HAVE_MPI
  MPI_Barrier(MPI_COMM_WORLD);
#endif
}

void Communicator::idleBarrier() const {
  if (!world_ || size_ == 1) return;
#ifdef DEMLAB_HAVE_MPI
  MPI_Request request;
  MPI_Ibarrier(MPI_COMM_WORLD, &request);
  for (int done = 0;;) {
    MPI_Test(&request, &done, MPI_STATUS_IGNORE);
    if (done) return;
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
#endif
}

}  // namespace demlab::mpi
