// Heartbeats between MPI ranks on different nodes, for the watchdog (cluster::startWatchdog).
//
// A rank stopped with SIGSTOP on this node is seen in /proc; one on another node is not. So
// the first rank of each node sends a UDP datagram every 100 ms to the first rank of the next
// node (in rank order, round the ring) and watches the one before it: a peer that has sent
// nothing for the timeout is stopped, or its node unreachable. Each watcher watches one peer,
// so a stopped rank is reported once. The datagrams come from a thread of their own, so a
// rank busy rendering (or waiting inside MPI) still sends them: only a stopped process (or
// node) goes quiet. No MPI here: the ranks exchange addresses through MPI beforehand.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

namespace pvrt::heartbeat {

// A UDP socket bound to every IPv4 address of this host, on a port the system picks.
class Socket {
 public:
  Socket();
  ~Socket();
  Socket(const Socket&) = delete;
  Socket& operator=(const Socket&) = delete;

  bool ok() const { return fd_ >= 0; }
  uint16_t port() const { return port_; }
  // Where to send: `host`'s first IPv4 address and `port`; false when the name does not resolve.
  bool aim(const std::string& host, uint16_t port);
  // One datagram carrying `rank` to where aim() pointed (nothing when it did not).
  void send(int32_t rank) const;
  // The rank in a datagram that came within `ms` milliseconds, or nullopt.
  std::optional<int32_t> receive(int ms) const;

 private:
  int fd_ = -1;
  uint16_t port_ = 0;
  bool aimed_ = false;
  unsigned char to_[16] = {};  // a sockaddr_in
};

// This host's name (gethostname), as the other ranks will resolve it.
std::string hostName();

}  // namespace pvrt::heartbeat
