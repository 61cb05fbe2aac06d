// Work a command leaves running on a thread of its own when Ctrl-C stops it (a renderer being
// made, a file being synced), which the process lets finish before it exits: an exit tears down
// the libraries such work runs in (software GL's and LLVM's global state, their exit handlers),
// and an exit that overtook it could hang or crash after the script had ended well.
#pragma once

namespace demlab {

// Counts one piece of background work while it lives; made at the start of the work's thread
// function (or before the thread starts), destroyed when the work is done.
class BackgroundWork {
 public:
  BackgroundWork();
  ~BackgroundWork();
  BackgroundWork(const BackgroundWork&) = delete;
  BackgroundWork& operator=(const BackgroundWork&) = delete;
};

// Returns true once no background work is running, false if some still is after `seconds`
// (a sync of a very slow disk: the exit then goes ahead). Changes nothing.
bool awaitBackgroundWork(double seconds);

}  // namespace demlab
