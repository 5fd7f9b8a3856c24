// The only file that knows about MPI.
#include <mpi.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <cstdio>
#include <cstring>
#include <limits>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include <unistd.h>

#include "core/error.h"
#include "core/output_files.h"
#include "core/prefault.h"
#include "parallel/cluster.h"
#include "parallel/heartbeat.h"

namespace pvrt::cluster {

namespace {

constexpr int kTagRequest = 101;
constexpr int kTagAssign = 102;
constexpr int kTagData = 103;

CommCounters gCounters;

// Adds the time of one communication call to the counters.
class Timed {
 public:
  explicit Timed(uint64_t bytes = 0) : t0_(MPI_Wtime()) {
    gCounters.bytesSent += bytes;
    if (bytes) ++gCounters.messages;
  }
  ~Timed() { gCounters.seconds += MPI_Wtime() - t0_; }

 private:
  double t0_;
};

void check(int rc, const char* what) {
  if (rc != MPI_SUCCESS) throw Error(ExitCode::Internal, std::string("MPI: ") + what + " failed");
}

// Waits for `request` by testing it with short sleeps in between. Open MPI's own waits
// spin, and a rank that spins while it waits (for the others at the barrier, for the
// master's answer) takes a CPU from a rank still rendering whenever ranks share CPUs.
void waitSleeping(MPI_Request& request, MPI_Status* status, const char* what) {
  for (int flag = 0;;) {
    check(MPI_Test(&request, &flag, status), what);
    if (flag) return;
    std::this_thread::sleep_for(std::chrono::microseconds(20));
  }
}

std::string gTransports = "not started";

// Open MPI's default point-to-point layer, where UCX is installed (Debian's build), starts by
// probing every device UCX knows: about 0.2 s of MPI_Init and MPI_Finalize in every rank
// (measured: 2 ranks of a tiny render under mpirun, 0.63-0.71 s whole, 0.41-0.47 s with ob1,
// 0.32-0.43 s with ob1 over vader and no UCX one-sided layer; docs/parallel.md). When every rank of the job runs on this node (mpirun says so through
// OMPI_COMM_WORLD_SIZE and OMPI_COMM_WORLD_LOCAL_SIZE) shared memory is all the job needs, so
// Open MPI is asked for ob1 over shared memory (vader) unless the user chose otherwise
// (`mpirun --mca pml ...` reaches the ranks as OMPI_MCA_pml, which is never overwritten), or
// set PVRT_MPI_SHARED_MEMORY=0. Ranks on several nodes keep Open MPI's own choice.
void preferSharedMemory() {
  const char* off = std::getenv("PVRT_MPI_SHARED_MEMORY");
  const char* size = std::getenv("OMPI_COMM_WORLD_SIZE");
  const char* local = std::getenv("OMPI_COMM_WORLD_LOCAL_SIZE");
  if ((off && std::strcmp(off, "0") == 0) || !size || !local || std::strcmp(size, local) != 0) {
    gTransports = "Open MPI's own choice";
    return;
  }
  setenv("OMPI_MCA_pml", "ob1", 0);
  setenv("OMPI_MCA_btl", "self,vader", 0);
  setenv("OMPI_MCA_osc", "^ucx", 0);
  // Each rank also maps its node with hwloc, and Open MPI asks it for the I/O devices too,
  // which only matter for choosing a network card: hwloc's plugins then walk the PCI bus,
  // load OpenCL and try the X displays :0 to :9 for GPUs. Measured on the 2-core machine,
  // 2 ranks of a 16 x 10 render, 5 alternating runs: MPI_Init 68-83 ms with them, 41-55 ms
  // without; the whole command 0.223-0.234 s against 0.182-0.207 s. A user's own
  // HWLOC_COMPONENTS is kept.
  setenv("HWLOC_COMPONENTS", "-pci,-opencl,-gl,-cuda,-nvml,-rsmi,-levelzero", 0);
  gTransports = std::string("one node: pml ") + std::getenv("OMPI_MCA_pml") + ", btl " + std::getenv("OMPI_MCA_btl") +
                ", osc " + std::getenv("OMPI_MCA_osc");
}

}  // namespace

const std::string& transports() { return gTransports; }

Session::Session() {
  int initialised = 0;
  MPI_Initialized(&initialised);
  if (initialised) return;
  preferSharedMemory();
  int provided = 0;
  check(MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided), "MPI_Init_thread");
  if (provided < MPI_THREAD_FUNNELED) throw Error(ExitCode::Internal, "MPI: the library lacks MPI_THREAD_FUNNELED");
  // Errors come back as return codes so that they become pvrt::Error, not a crash.
  MPI_Comm_set_errhandler(MPI_COMM_WORLD, MPI_ERRORS_RETURN);
}

Session::~Session() {
  int finalised = 0;
  MPI_Finalized(&finalised);
  if (!finalised) MPI_Finalize();
}

int rank() {
  int r = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &r);
  return r;
}

int size() {
  int n = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &n);
  return n;
}

std::string processorName() {
  char name[MPI_MAX_PROCESSOR_NAME] = {};
  int len = 0;
  MPI_Get_processor_name(name, &len);
  return std::string(name, size_t(len));
}

NodePlace placeOnNode(const std::vector<int>& cpus) {
  MPI_Comm node;
  check(MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, 0, MPI_INFO_NULL, &node), "MPI_Comm_split_type");
  int me = 0, n = 1;
  MPI_Comm_rank(node, &me);
  MPI_Comm_size(node, &n);
  // Each rank's CPUs as a bitmap of 1024 CPUs (CPU_SETSIZE); higher ones fold onto them,
  // which can only make two different masks look alike.
  constexpr int kWords = 16;
  std::vector<uint64_t> mine(kWords, 0), all(size_t(kWords) * size_t(n));
  for (int c : cpus) mine[size_t(c / 64) % kWords] |= uint64_t(1) << (c % 64);
  const int rc = MPI_Allgather(mine.data(), kWords, MPI_UINT64_T, all.data(), kWords, MPI_UINT64_T, node);
  MPI_Comm_free(&node);
  check(rc, "MPI_Allgather");
  NodePlace place;
  place.nodeRanks = n;
  place.slots = 0;
  for (int r = 0; r < n; ++r) {
    if (!std::equal(mine.begin(), mine.end(), all.begin() + std::ptrdiff_t(r) * kWords)) continue;
    if (r < me) ++place.slot;
    ++place.slots;
  }
  return place;
}

namespace {

// The state letter of process `pid` (/proc/PID/stat: "pid (comm) S ..."), 0 when gone.
char processState(int pid) {
  char path[64];
  std::snprintf(path, sizeof path, "/proc/%d/stat", pid);
  std::FILE* f = std::fopen(path, "r");
  if (!f) return 0;
  char buf[512];
  const size_t n = std::fread(buf, 1, sizeof buf - 1, f);
  std::fclose(f);
  buf[n] = 0;
  const char* close = std::strrchr(buf, ')');  // the command name may hold anything, even ')'
  return close && close[1] == ' ' ? close[2] : 0;
}

// The ring of heartbeats between nodes (parallel/heartbeat.h); collective over all ranks,
// `first` for the first rank of each node.
void startHeartbeats(double seconds, bool first) {
  struct Card {
    int32_t rank = 0, pid = 0, port = 0, inRing = 0;
    char host[128] = {};
  };
  // Only a node's first rank, and only with a watchdog, opens a socket.
  std::shared_ptr<heartbeat::Socket> socket;
  if (seconds > 0 && first) socket = std::make_shared<heartbeat::Socket>();
  Card mine;
  mine.rank = rank();
  mine.pid = int32_t(::getpid());
  mine.inRing = socket && socket->ok();
  mine.port = socket ? socket->port() : 0;
  std::snprintf(mine.host, sizeof mine.host, "%s", heartbeat::hostName().c_str());
  std::vector<Card> cards(static_cast<size_t>(size()));
  check(MPI_Allgather(&mine, sizeof(Card), MPI_BYTE, cards.data(), sizeof(Card), MPI_BYTE, MPI_COMM_WORLD),
        "MPI_Allgather");
  if (!mine.inRing) return;
  std::vector<size_t> ring;  // the first ranks of the nodes, in rank order
  for (size_t i = 0; i < cards.size(); ++i)
    if (cards[i].inRing) ring.push_back(i);
  if (ring.size() < 2) return;
  const size_t at = size_t(std::find(ring.begin(), ring.end(), size_t(mine.rank)) - ring.begin());
  const Card& next = cards[ring[(at + 1) % ring.size()]];
  const Card watched = cards[ring[(at + ring.size() - 1) % ring.size()]];
  if (!socket->aim(next.host, uint16_t(next.port)))
    std::fprintf(stderr, "pvrt: warning: rank %d cannot resolve the host name '%s' of rank %d: a stop of rank %d "
                 "goes unnoticed\n", mine.rank, next.host, next.rank, next.rank);
  std::thread([socket, seconds, me = mine.rank, watched] {
    using Clock = std::chrono::steady_clock;
    Clock::time_point heard = Clock::now(), last = heard;
    for (;;) {
      socket->send(me);
      const Clock::time_point until = Clock::now() + std::chrono::milliseconds(100);
      for (Clock::time_point t = Clock::now(); t < until; t = Clock::now()) {
        const auto ms = std::chrono::duration_cast<std::chrono::milliseconds>(until - t).count();
        if (socket->receive(int(std::max<long>(1, long(ms)))) == watched.rank) heard = Clock::now();
      }
      const Clock::time_point now = Clock::now();
      // Far more than 100 ms since the last look: this rank was stopped itself.
      if (now - last > std::chrono::seconds(1)) heard = now;
      last = now;
      // The last heartbeat came up to one period before the stop: the silence must be the
      // timeout and a period, for the stop itself to have lasted the timeout.
      if (std::chrono::duration<double>(now - heard).count() < seconds + 0.1) continue;
      std::fprintf(stderr,
                   "pvrt: error: rank %d (pid %d on %s) has sent no heartbeat for %g s (stopped, or its node cut "
                   "off); ending the job (--mpi-timeout %g)\n",
                   watched.rank, watched.pid, watched.host, seconds, seconds);
      std::fflush(stderr);
      removeStagedFilesNow();  // rank 0's temporaries: _exit runs no destructors
      _exit(int(ExitCode::Stalled));
    }
  }).detach();
}

}  // namespace

void startWatchdog(double seconds) {
  MPI_Comm node;
  check(MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, 0, MPI_INFO_NULL, &node), "MPI_Comm_split_type");
  int n = 1, nodeRank = 0;
  MPI_Comm_size(node, &n);
  MPI_Comm_rank(node, &nodeRank);
  const int mine[2] = {rank(), int(::getpid())};
  std::vector<int> all(size_t(2 * n));
  const int rc = MPI_Allgather(mine, 2, MPI_INT, all.data(), 2, MPI_INT, node);
  MPI_Comm_free(&node);
  check(rc, "MPI_Allgather");
  // Tests: every rank as if on a node of its own, watched by heartbeats alone.
  const char* alone = std::getenv("PVRT_WATCHDOG_HEARTBEATS_ONLY");
  const bool heartbeatsOnly = alone && std::strcmp(alone, "1") == 0;
  startHeartbeats(seconds, heartbeatsOnly || nodeRank == 0);
  if (!(seconds > 0) || n < 2 || heartbeatsOnly) return;
  std::thread([seconds, all, n, me = mine[0]] {
    using Clock = std::chrono::steady_clock;
    std::vector<Clock::time_point> stoppedSince(static_cast<size_t>(n), Clock::time_point{});
    std::vector<bool> stopped(size_t(n), false);
    Clock::time_point last = Clock::now();
    for (;;) {
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
      const Clock::time_point now = Clock::now();
      // Far more than 100 ms since the last look: this rank was stopped itself.
      const bool selfStopped = now - last > std::chrono::seconds(1);
      last = now;
      int longest = -1, lowestRunning = -1;
      for (int i = 0; i < n; ++i) {
        const int worldRank = all[size_t(2 * i)], pid = all[size_t(2 * i + 1)];
        const bool isStopped = worldRank != me && processState(pid) == 'T';
        if (isStopped && (!stopped[size_t(i)] || selfStopped)) stoppedSince[size_t(i)] = now;
        stopped[size_t(i)] = isStopped;
        if (!isStopped && (lowestRunning < 0 || worldRank < lowestRunning)) lowestRunning = worldRank;
        if (isStopped && std::chrono::duration<double>(now - stoppedSince[size_t(i)]).count() >= seconds)
          longest = i;
      }
      if (longest < 0 || lowestRunning != me) continue;
      std::fprintf(stderr,
                   "pvrt: error: rank %d (pid %d) has been stopped for %g s; ending the job (--mpi-timeout %g)\n",
                   all[size_t(2 * longest)], all[size_t(2 * longest + 1)], seconds, seconds);
      std::fflush(stderr);
      removeStagedFilesNow();  // rank 0's temporaries: _exit runs no destructors
      _exit(int(ExitCode::Stalled));
    }
  }).detach();
}

const CommCounters& counters() { return gCounters; }

bool anyFailed(bool failedHere) {
  int mine = failedHere ? 1 : 0, any = 0;
  check(MPI_Allreduce(&mine, &any, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD), "MPI_Allreduce");
  return any != 0;
}

std::string firstError(const std::string& mine) {
  // The lowest failing rank broadcasts its message.
  const int me = rank();
  int candidate = mine.empty() ? size() : me, first = 0;
  check(MPI_Allreduce(&candidate, &first, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD), "MPI_Allreduce");
  if (first >= size()) return {};
  int len = me == first ? int(mine.size()) : 0;
  MPI_Bcast(&len, 1, MPI_INT, first, MPI_COMM_WORLD);
  std::string text(size_t(len), '\0');
  if (me == first) text = mine;
  MPI_Bcast(text.data(), len, MPI_CHAR, first, MPI_COMM_WORLD);
  return text;
}

double barrier() {
  const double t0 = MPI_Wtime();
  MPI_Request request;
  check(MPI_Ibarrier(MPI_COMM_WORLD, &request), "MPI_Ibarrier");
  waitSleeping(request, MPI_STATUS_IGNORE, "MPI_Ibarrier");
  return MPI_Wtime() - t0;
}

void abortAll(int code) {
  MPI_Abort(MPI_COMM_WORLD, code);
  std::abort();  // not reached
}

namespace {

template <class T>
MPI_Datatype mpiType();
template <>
MPI_Datatype mpiType<float>() { return MPI_FLOAT; }
template <>
MPI_Datatype mpiType<uint32_t>() { return MPI_UINT32_T; }

// MPI counts are ints: a buffer of more elements cannot travel in one message.
int countOf(size_t elements) {
  if (elements > size_t(std::numeric_limits<int>::max()))
    throw Error(ExitCode::Internal, "MPI: a buffer of " + std::to_string(elements) +
                                        " elements is too large for one message (at most 2^31 - 1)");
  return int(elements);
}

template <class T>
std::vector<T> gathervOf(const std::vector<T>& mine) {
  Timed timed(mine.size() * sizeof(T));
  const int n = size(), me = rank();
  int count = countOf(mine.size());
  std::vector<int> counts(size_t(me == 0 ? n : 0)), displs;
  check(MPI_Gather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, MPI_COMM_WORLD), "MPI_Gather");
  std::vector<T> all;
  if (me == 0) {
    displs.assign(size_t(n), 0);
    size_t total = 0;
    for (int r = 0; r < n; ++r) {
      displs[size_t(r)] = countOf(total);
      total += size_t(counts[size_t(r)]);
    }
    countOf(total);
    // Its pages faulted in by the rank's threads first, not one by one inside MPI's copy (12 MB
    // for a 1280x800 image of floats: about 3000 faults, several ms, on the render's critical path).
    resizePrefaulted(all, total, 0);
  }
  check(MPI_Gatherv(mine.data(), count, mpiType<T>(), all.data(), counts.data(), displs.data(), mpiType<T>(), 0,
                    MPI_COMM_WORLD),
        "MPI_Gatherv");
  return all;
}

template <class T>
void sendTo(int to, const std::vector<T>& data) {
  Timed timed(data.size() * sizeof(T));
  int count = countOf(data.size());
  check(MPI_Send(&count, 1, MPI_INT, to, kTagData, MPI_COMM_WORLD), "MPI_Send");
  check(MPI_Send(data.data(), count, mpiType<T>(), to, kTagData, MPI_COMM_WORLD), "MPI_Send");
}

// Receives what sendTo sent, appended to `held` (no copy in between).
template <class T>
void receiveAppend(int from, std::vector<T>& held) {
  Timed timed;
  int count = 0;
  check(MPI_Recv(&count, 1, MPI_INT, from, kTagData, MPI_COMM_WORLD, MPI_STATUS_IGNORE), "MPI_Recv");
  const size_t at = held.size();
  countOf(at + size_t(count));
  held.resize(at + size_t(count));
  check(MPI_Recv(held.data() + at, count, mpiType<T>(), from, kTagData, MPI_COMM_WORLD, MPI_STATUS_IGNORE),
        "MPI_Recv");
}

template <class T>
std::vector<T> recursiveDoublingOf(std::vector<T> held) {
  const int me = rank(), n = size();
  for (int mask = 1; mask < n; mask <<= 1) {
    if (me & mask) {  // hand everything held to the partner below, and stop
      sendTo(me - mask, held);
      return {};
    }
    if (me + mask < n) receiveAppend(me + mask, held);
  }
  return held;  // rank 0
}

}  // namespace

std::vector<float> gatherv(const std::vector<float>& mine) { return gathervOf(mine); }
std::vector<uint32_t> gatherv(const std::vector<uint32_t>& mine) { return gathervOf(mine); }
std::vector<float> gatherRecursiveDoubling(std::vector<float> mine) { return recursiveDoublingOf(std::move(mine)); }
std::vector<uint32_t> gatherRecursiveDoubling(std::vector<uint32_t> mine) {
  return recursiveDoublingOf(std::move(mine));
}

std::vector<double> pingPong(size_t bytes, int reps) {
  const int me = rank();
  std::vector<char> buffer(std::max<size_t>(bytes, 1));
  std::vector<double> times;
  check(MPI_Barrier(MPI_COMM_WORLD), "MPI_Barrier");
  if (me <= 1 && size() > 1) {
    const int count = int(bytes), other = 1 - me;
    for (int k = 0; k < reps; ++k) {
      const double t0 = MPI_Wtime();
      if (me == 0) {
        check(MPI_Send(buffer.data(), count, MPI_BYTE, other, kTagData, MPI_COMM_WORLD), "MPI_Send");
        check(MPI_Recv(buffer.data(), count, MPI_BYTE, other, kTagData, MPI_COMM_WORLD, MPI_STATUS_IGNORE),
              "MPI_Recv");
        times.push_back(MPI_Wtime() - t0);
      } else {
        check(MPI_Recv(buffer.data(), count, MPI_BYTE, other, kTagData, MPI_COMM_WORLD, MPI_STATUS_IGNORE),
              "MPI_Recv");
        check(MPI_Send(buffer.data(), count, MPI_BYTE, other, kTagData, MPI_COMM_WORLD), "MPI_Send");
      }
    }
  }
  check(MPI_Barrier(MPI_COMM_WORLD), "MPI_Barrier");
  return me == 0 ? times : std::vector<double>{};
}

std::vector<double> gatherFixed(const std::vector<double>& mine) {
  Timed timed(mine.size() * sizeof(double));
  std::vector<double> all(rank() == 0 ? mine.size() * size_t(size()) : 0);
  check(MPI_Gather(mine.data(), int(mine.size()), MPI_DOUBLE, all.data(), int(mine.size()), MPI_DOUBLE, 0,
                   MPI_COMM_WORLD),
        "MPI_Gather");
  return all;
}

struct WorkRequest::State {
  MPI_Request receive = MPI_REQUEST_NULL;
  std::vector<int> items;
  bool pending = false;
};

WorkRequest::WorkRequest() : s_(std::make_unique<State>()) {}
WorkRequest::~WorkRequest() {
  if (s_->pending) MPI_Wait(&s_->receive, MPI_STATUS_IGNORE);
}

void WorkRequest::post(int want) {
  Timed timed(sizeof(int));
  s_->items.assign(size_t(std::max(1, want)), -1);
  check(MPI_Irecv(s_->items.data(), int(s_->items.size()), MPI_INT, 0, kTagAssign, MPI_COMM_WORLD, &s_->receive),
        "MPI_Irecv");
  s_->pending = true;
  check(MPI_Send(&want, 1, MPI_INT, 0, kTagRequest, MPI_COMM_WORLD), "MPI_Send");
}

bool WorkRequest::pending() const { return s_->pending; }

bool WorkRequest::ready() {
  if (!s_->pending) return false;
  Timed timed;
  int flag = 0;
  check(MPI_Test(&s_->receive, &flag, MPI_STATUS_IGNORE), "MPI_Test");
  if (flag) s_->pending = false;  // MPI_Test freed the request; take() reads the items
  return flag != 0;
}

std::vector<int> WorkRequest::take() {
  Timed timed;
  if (s_->pending) {
    waitSleeping(s_->receive, MPI_STATUS_IGNORE, "MPI_Test");
    s_->pending = false;
  }
  std::vector<int> items;
  for (int i : s_->items)
    if (i >= 0) items.push_back(i);
  s_->items.clear();
  return items;
}

std::optional<Request> pollRequest() {
  Timed timed;
  int flag = 0;
  MPI_Status status;
  check(MPI_Iprobe(MPI_ANY_SOURCE, kTagRequest, MPI_COMM_WORLD, &flag, &status), "MPI_Iprobe");
  if (!flag) return std::nullopt;
  Request r;
  check(MPI_Recv(&r.want, 1, MPI_INT, status.MPI_SOURCE, kTagRequest, MPI_COMM_WORLD, MPI_STATUS_IGNORE),
        "MPI_Recv");
  r.worker = status.MPI_SOURCE;
  return r;
}

void answer(int worker, const std::vector<int>& items) {
  Timed timed(items.size() * sizeof(int));
  check(MPI_Send(items.data(), int(items.size()), MPI_INT, worker, kTagAssign, MPI_COMM_WORLD), "MPI_Send");
}

}  // namespace pvrt::cluster
