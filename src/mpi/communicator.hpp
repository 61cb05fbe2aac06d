// The ranks of a distributed run and the collective operations the domain decomposition needs
// (doc/plans/mpi.md): sums and extremes over all ranks, and the exchange of byte buffers
// between every pair of ranks (each rank hands one buffer per destination and receives one
// per source). Built with MPI (DEMLAB_MPI), the world communicator once MPI_Init has run;
// without MPI, or before MPI_Init, a single rank for which every collective is the identity,
// so the code above it runs unchanged in a serial build.
//
// Every collective must be called by every rank, in the same order, with the same sizes where
// the comment says so: that is MPI's rule, and a rank that skips one deadlocks the others.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace demlab::mpi {

class Communicator {
 public:
  // Returns the world: every rank of the run (one, without MPI or before MPI_Init).
  static Communicator& world();

  // Returns a single-rank communicator, whatever MPI holds: for serial uses and tests.
  static Communicator& self();

  int rank() const { return rank_; }
  int size() const { return size_; }
  bool distributed() const { return size_ > 1; }

  // Replaces each value by its sum (max, min) over the ranks, element by element; every rank
  // passes the same count. The sums of doubles are taken in rank order on one rank and
  // broadcast, so every rank gets the same bits for the same inputs; that gathers every rank's
  // vector on rank 0, so it is for a few values (energies, forces on walls): long sums go as
  // integers (Partition quantizes its weights), which MPI reduces exactly in one step.
  void sum(std::vector<double>& values) const;
  void sum(std::vector<int64_t>& values) const;
  void max(std::vector<double>& values) const;
  void min(std::vector<double>& values) const;
  double sum(double v) const;
  int64_t sum(int64_t v) const;
  double max(double v) const;
  double min(double v) const;

  // Returns every rank's values, rank by rank (each rank passes the same count).
  std::vector<double> gather(const std::vector<double>& values) const;

  // Returns every rank's buffer, indexed by rank (each rank passes its own, of any size).
  std::vector<std::vector<char>> gatherBytes(const std::vector<char>& mine) const;

  // Sends out[k] to rank k (out has size() buffers; out[rank()] comes back to this rank
  // untouched) and returns the buffers the ranks sent here, indexed by source rank.
  std::vector<std::vector<char>> exchange(const std::vector<std::vector<char>>& out) const;

  // Sends out[i] to rank to[i] and receives in[j] from rank from[j], point to point with those
  // ranks only (the step's exchange with the neighbouring ranks; exchange() above talks to every
  // rank). in[j] must already have the size rank from[j] sends: the ranks agree on the lists
  // beforehand (GhostPlan makes them with one exchange() at a search). Not a collective: only
  // the ranks named take part, each send matched by a receive.
  void exchangeWith(const std::vector<int>& to, const std::vector<std::vector<char>>& out,
                    const std::vector<int>& from, std::vector<std::vector<char>>& in) const;

  // Waits until every rank has come here.
  void barrier() const;
  // barrier, sleeping a millisecond between looks: for ranks that wait seconds while one works
  // alone, so that they leave their cores to other processes (a blocking collective spins on
  // its core unless the node is oversubscribed). Collective.
  void idleBarrier() const;

  // exchangeWith in halves (PostedExchange), so that a rank works while its messages travel.
  friend class PostedExchange;

 private:
  Communicator(int rank, int size, bool world) : rank_(rank), size_(size), world_(world) {}
  int rank_ = 0, size_ = 1;
  bool world_ = false;  // MPI_COMM_WORLD (else the single rank)
};

// Communicator::exchangeWith in three calls: post() sends and posts the receives, receive()
// waits for what this rank receives, and the sends complete later (finishSends(), or the next
// post(), or the destructor). A rank that works between post() and receive() hides the
// messages' travel and the other ranks' lateness up to that work's time; and as a rank does
// not wait for the others to take its own messages, it waits only for theirs. The buffers
// named in post() must stay as they are (out) and alive (out and in) until the sends (out) or
// receive() (in) complete: the owner keeps them beside this object, declared before it so
// that they outlive its destructor. Not a collective, as exchangeWith.
class PostedExchange {
 public:
  PostedExchange();
  ~PostedExchange();
  PostedExchange(const PostedExchange&) = delete;
  PostedExchange& operator=(const PostedExchange&) = delete;

  // Completes the sends of the last post(), then sends out[i] to rank to[i] and posts the
  // receive of in[j] from rank from[j] (in[j] sized as exchangeWith's). On one rank it copies
  // what this rank sends itself now. Changes the requests held.
  void post(const Communicator& comm, const std::vector<int>& to,
            const std::vector<std::vector<char>>& out, const std::vector<int>& from,
            std::vector<std::vector<char>>& in);
  // Waits until the buffers of the last post()'s receives are filled. Changes them.
  void receive();
  // Waits until the last post()'s sends are complete (their buffers may then change).
  void finishSends();

 private:
  struct Requests;
  std::unique_ptr<Requests> pending_;
};

// Starts MPI for the process's life when it was launched by mpirun as one of several ranks
// (OpenMPI's or a PMI launcher's environment says so), so that Communicator::world() is the
// run's ranks; a process started alone, or as mpirun's only rank, stays one rank and pays no
// MPI start-up. Ends MPI when destroyed.
class Session {
 public:
  Session(int* argc, char*** argv);
  ~Session();
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;

  // How the ranks ended a script they all ran (endScript).
  struct Ending {
    int worst = 0;       // the largest exit status over the ranks
    int firstFailed = -1;  // the lowest rank whose status is not 0, or -1
  };
  // Ends a batch script on every rank with this rank's exit status (0: it finished). Returns
  // when every rank has ended it. A rank whose script failed waits at most `patience` seconds
  // for the others: an error that comes from the scene or the script's words comes on every
  // rank at the same command; when it does not (one rank could not write a file), the others
  // may be waiting in a step's exchange for ever, so the run is aborted (MPI_Abort, exit code
  // status) after writing lastWords to stderr, and this does not return. On a single rank:
  // {status, status ? 0 : -1}.
  Ending endScript(int status, double patience, const std::string& lastWords) const;

 private:
  bool started_ = false;
};

// Returns true if this build has MPI.
bool built();

// Returns true when a launcher (mpirun: OpenMPI's environment, or a PMI one's) started this
// process, with any number of ranks.
bool launched();

}  // namespace demlab::mpi
