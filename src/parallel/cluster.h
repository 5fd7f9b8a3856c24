// The distributed half of the parallel seam: the handful of message-passing operations
// the MPI backend needs, as plain C++ over std::vector. cluster_mpi.cpp is the only
// file that knows about MPI; rendering code sees ranks, payloads and a work queue.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace pvrt::cluster {

// Starts MPI (thread level FUNNELED: OpenMP threads inside a rank never call MPI) for
// the lifetime of the object, and finalises it afterwards.
class Session {
 public:
  Session();
  ~Session();
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;
};

// What Session asked of Open MPI's transports, for --stats (cluster_mpi.cpp says why).
const std::string& transports();

int rank();
int size();
std::string processorName();

// Collective: this rank's place among the ranks of its node (MPI_COMM_TYPE_SHARED) that
// may run on exactly the same CPUs `cpus`: it is `slot` of `slots` of them. The ranks of
// `nodeRanks` on the node in all.
struct NodePlace {
  int slot = 0, slots = 1, nodeRanks = 1;
};
NodePlace placeOnNode(const std::vector<int>& cpus);

// Watches the other ranks of this node (collective: every rank calls it once). When one of
// them has been stopped (SIGSTOP: state T in /proc; a debugger's tracing stop does not
// count) for `seconds`, the lowest rank of the node that is not stopped prints which and ends
// the job with exit code 75 instead of waiting for it for ever. A rank's own stop (the whole
// job stopped with Ctrl-Z, say) restarts its clocks. 0 seconds: no watchdog. Ranks on other
// nodes cannot be seen in /proc: the first ranks of the nodes send each other heartbeats
// round a ring (parallel/heartbeat.h), and one that goes quiet for `seconds` ends the job the
// same way. PVRT_WATCHDOG_HEARTBEATS_ONLY=1 treats every rank as a node of its own (tests).
void startWatchdog(double seconds);

// Communication cost of this rank so far: seconds spent in calls and bytes sent.
struct CommCounters {
  double seconds = 0;
  uint64_t bytesSent = 0;
  uint64_t messages = 0;
};
const CommCounters& counters();

// Collective: true on every rank when any rank passes true. Lets all ranks stop
// together, with one message, when one of them fails (never a hang).
bool anyFailed(bool failedHere);
// Collective: the first error text of the lowest failing rank, on every rank.
std::string firstError(const std::string& mine);

// Collective: waits for every rank; returns the seconds this rank waited (idle time).
double barrier();
// Ends every rank of the job at once with `code` (for failures past the agreement points).
[[noreturn]] void abortAll(int code);

// Collective: rank 0 receives every rank's buffer, concatenated in rank order
// (MPI_Gatherv: any number of ranks, uneven sizes). Empty on other ranks. Of floats, or of
// 32-bit words (a render's payload: sRGB bytes and floats packed as it needs them; words
// rather than bytes, so that the largest image's payload still counts under 2^31).
std::vector<float> gatherv(const std::vector<float>& mine);
std::vector<uint32_t> gatherv(const std::vector<uint32_t>& mine);
// Collective: rank 0 receives `mine` from every rank (all of the same length).
std::vector<double> gatherFixed(const std::vector<double>& mine);
// Collective, the same result as gatherv() (but the order of the buffers) by recursive
// doubling: in round k (k = 0, 1, ...) every rank r still holding data whose bit k is set
// hands all it holds to rank r - 2^k, which appends it; after ceil(log2 P) rounds rank 0
// holds everything. Any number of ranks; no rank ever holds more than rank 0 finally does.
// Empty on other ranks than 0.
std::vector<float> gatherRecursiveDoubling(std::vector<float> mine);
std::vector<uint32_t> gatherRecursiveDoubling(std::vector<uint32_t> mine);
// Ranks 0 and 1 send `bytes` back and forth `reps` times; the round trips' seconds on rank
// 0 (empty on the other ranks). Collective: every rank calls it, ranks above 1 wait.
std::vector<double> pingPong(size_t bytes, int reps);

// The dynamic work queue of the master/worker strategy; items travel in batches.
// Worker side: one request at a time, posted before the worker runs out, so that the
// answer comes while it renders what it holds.
class WorkRequest {
 public:
  WorkRequest();
  ~WorkRequest();
  WorkRequest(const WorkRequest&) = delete;
  WorkRequest& operator=(const WorkRequest&) = delete;
  void post(int want);  // asks rank 0 for up to `want` items
  bool pending() const;
  bool ready();             // the answer has come (never blocks)
  std::vector<int> take();  // waits for the answer: the items, empty when none are left

 private:
  struct State;
  std::unique_ptr<State> s_;
};
// Master side: the next waiting request, if any (never blocks), and its answer.
struct Request {
  int worker = -1;
  int want = 0;
};
std::optional<Request> pollRequest();
void answer(int worker, const std::vector<int>& items);

}  // namespace pvrt::cluster
