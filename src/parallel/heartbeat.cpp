#include "parallel/heartbeat.h"

#include <arpa/inet.h>
#include <netdb.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cstring>

namespace pvrt::heartbeat {

Socket::Socket() {
  fd_ = ::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC | SOCK_NONBLOCK, 0);
  if (fd_ < 0) return;
  sockaddr_in any{};
  any.sin_family = AF_INET;
  any.sin_addr.s_addr = htonl(INADDR_ANY);
  any.sin_port = 0;
  socklen_t len = sizeof any;
  if (::bind(fd_, reinterpret_cast<const sockaddr*>(&any), sizeof any) != 0 ||
      ::getsockname(fd_, reinterpret_cast<sockaddr*>(&any), &len) != 0) {
    ::close(fd_);
    fd_ = -1;
    return;
  }
  port_ = ntohs(any.sin_port);
}

Socket::~Socket() {
  if (fd_ >= 0) ::close(fd_);
}

bool Socket::aim(const std::string& host, uint16_t port) {
  addrinfo hints{};
  hints.ai_family = AF_INET;
  hints.ai_socktype = SOCK_DGRAM;
  addrinfo* found = nullptr;
  if (::getaddrinfo(host.c_str(), nullptr, &hints, &found) != 0 || !found) return false;
  sockaddr_in to{};
  std::memcpy(&to, found->ai_addr, sizeof to);
  ::freeaddrinfo(found);
  to.sin_port = htons(port);
  static_assert(sizeof to_ >= sizeof to);
  std::memcpy(to_, &to, sizeof to);
  aimed_ = true;
  return true;
}

void Socket::send(int32_t rank) const {
  if (!ok() || !aimed_) return;
  const uint32_t wire = htonl(uint32_t(rank));
  // Lost or refused datagrams are no matter: the next one comes 100 ms later.
  (void)::sendto(fd_, &wire, sizeof wire, MSG_DONTWAIT, reinterpret_cast<const sockaddr*>(to_), sizeof(sockaddr_in));
}

std::optional<int32_t> Socket::receive(int ms) const {
  if (!ok()) return std::nullopt;
  pollfd p{fd_, POLLIN, 0};
  if (::poll(&p, 1, ms) <= 0) return std::nullopt;
  uint32_t wire = 0;
  if (::recv(fd_, &wire, sizeof wire, MSG_DONTWAIT) != ssize_t(sizeof wire)) return std::nullopt;
  return int32_t(ntohl(wire));
}

std::string hostName() {
  char name[256] = {};
  if (::gethostname(name, sizeof name - 1) != 0) return "localhost";
  return name;
}

}  // namespace pvrt::heartbeat
