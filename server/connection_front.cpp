// The accept path of the HTTP service (server/connection_front.h): one epoll loop for every
// connection that waits, a fixed set of workers for complete requests.
//
// Ownership: a connection that waits (for its request, or idle between two) belongs to the loop's
// thread, which alone reads into its buffer and alone closes it; a connection whose request is
// complete sits in `ready` and then belongs to the worker that took it, until the worker closes it
// or hands it back. The table of connections, the queues and the per-client counts are guarded by
// one mutex.
#include "server/connection_front.h"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netdb.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/epoll.h>
#include <sys/eventfd.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <condition_variable>
#include <cstring>
#include <deque>
#include <map>
#include <mutex>
#include <optional>
#include <string_view>
#include <thread>
#include <vector>

namespace lambert {
namespace {

using Clock = std::chrono::steady_clock;
using std::chrono::milliseconds;

int remaining_ms(Clock::time_point deadline) {
  const auto left = std::chrono::duration_cast<milliseconds>(deadline - Clock::now()).count();
  return static_cast<int>(std::clamp<long long>(left, 0, 1 << 30));
}

bool poll_for(int fd, short events, int timeout_ms) {
  pollfd p{fd, events, 0};
  for (;;) {
    const int r = ::poll(&p, 1, timeout_ms);
    if (r < 0 && errno == EINTR) continue;
    return r > 0 && (p.revents & (events | POLLHUP | POLLERR));
  }
}

// "ip", port of a socket address.
std::pair<std::string, int> address_text(const sockaddr_storage& a) {
  char text[INET6_ADDRSTRLEN] = "";
  if (a.ss_family == AF_INET) {
    const auto& v4 = reinterpret_cast<const sockaddr_in&>(a);
    ::inet_ntop(AF_INET, &v4.sin_addr, text, sizeof text);
    return {text, ntohs(v4.sin_port)};
  }
  if (a.ss_family == AF_INET6) {
    const auto& v6 = reinterpret_cast<const sockaddr_in6&>(a);
    ::inet_ntop(AF_INET6, &v6.sin6_addr, text, sizeof text);
    return {text, ntohs(v6.sin6_port)};
  }
  return {"", 0};
}

// A short answer written without a worker (best effort: the socket may be full or gone), in the
// service's error format (SPEC §4).
void answer_and_close(int fd, int status, const char* reason, const char* code, const std::string& message) {
  const std::string body = "{\"error\":{\"code\":\"" + std::string(code) + "\",\"message\":\"" + message +
                           "\",\"pointer\":\"\"}}\n";
  std::string head = "HTTP/1.1 " + std::to_string(status) + " " + reason +
                     "\r\nContent-Type: application/json\r\nConnection: close\r\nContent-Length: " +
                     std::to_string(body.size()) + "\r\n";
  if (status == 503) head += "Retry-After: 5\r\n";
  const std::string text = head + "\r\n" + body;
  [[maybe_unused]] const ssize_t n = ::send(fd, text.data(), text.size(), MSG_NOSIGNAL | MSG_DONTWAIT);
  ::shutdown(fd, SHUT_WR);
  ::close(fd);
}

bool iequals(std::string_view a, std::string_view b) {
  return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
           return std::tolower(static_cast<unsigned char>(x)) == std::tolower(static_cast<unsigned char>(y));
         });
}

// What the loop needs to know of a request's head: where it ends and how its body comes.
struct Head {
  enum class Kind { Incomplete, TooLarge, Complete } kind = Kind::Incomplete;
  std::size_t end = 0;                 // bytes of request line and headers, with the blank line
  std::optional<std::size_t> length;   // Content-Length, when that is how the body comes
  bool other_body = false;             // chunked, or a client that waits for 100 Continue
};

Head parse_head(std::string_view buffer, std::size_t max_header_bytes) {
  Head h;
  const auto blank = buffer.find("\r\n\r\n");
  if (blank == std::string_view::npos || blank + 4 > max_header_bytes) {
    h.kind = buffer.size() > max_header_bytes || blank != std::string_view::npos ? Head::Kind::TooLarge
                                                                                   : Head::Kind::Incomplete;
    return h;
  }
  h.kind = Head::Kind::Complete;
  h.end = blank + 4;
  std::size_t pos = buffer.find("\r\n") + 2;  // after the request line
  while (pos < blank + 2) {
    const std::size_t eol = buffer.find("\r\n", pos);
    const std::string_view line = buffer.substr(pos, eol - pos);
    pos = eol + 2;
    const auto colon = line.find(':');
    if (colon == std::string_view::npos) continue;  // the worker's parser answers 400
    std::string_view name = line.substr(0, colon), value = line.substr(colon + 1);
    while (!value.empty() && (value.front() == ' ' || value.front() == '\t')) value.remove_prefix(1);
    if (iequals(name, "Content-Length")) {
      std::size_t n = 0;
      bool digits = !value.empty() && value.size() <= 18;
      for (char c : value) digits = digits && c >= '0' && c <= '9', n = n * 10 + static_cast<std::size_t>(c - '0');
      if (digits) h.length = n;
      else h.other_body = true;  // malformed: let the worker's parser answer it
    } else if (iequals(name, "Transfer-Encoding") || iequals(name, "Expect")) {
      h.other_body = true;
    }
  }
  return h;
}

}  // namespace

// ---- a worker's connection -----------------------------------------------------------------------

ssize_t Connection::read(char* data, std::size_t size) {
  if (consumed_ < buffer_.size()) {
    const std::size_t n = std::min(size, buffer_.size() - consumed_);
    std::memcpy(data, buffer_.data() + consumed_, n);
    consumed_ += n;
    return static_cast<ssize_t>(n);
  }
  for (;;) {
    // A body must keep up min_rate_ after the grace: the time allowed grows with what arrived.
    auto allowed = request_start_ + grace_;
    if (min_rate_ > 0)
      allowed += std::chrono::duration_cast<Clock::duration>(
          std::chrono::duration<double>(static_cast<double>(read_from_socket_) / min_rate_));
    const int wait = std::min(static_cast<int>(read_timeout_.count()), min_rate_ > 0 ? remaining_ms(allowed) : 1 << 30);
    if (!poll_for(fd_, POLLIN, wait)) return -1;
    const ssize_t n = ::recv(fd_, data, size, 0);
    if (n < 0 && (errno == EINTR || errno == EAGAIN)) continue;
    if (n > 0) read_from_socket_ += static_cast<std::size_t>(n);
    return n;
  }
}

ssize_t Connection::write(const char* data, std::size_t size) {
  std::size_t sent = 0;
  while (sent < size) {
    if (!poll_for(fd_, POLLOUT, static_cast<int>(write_timeout_.count()))) return -1;
    const ssize_t n = ::send(fd_, data + sent, size - sent, MSG_NOSIGNAL);
    if (n < 0 && (errno == EINTR || errno == EAGAIN)) continue;
    if (n <= 0) return -1;
    sent += static_cast<std::size_t>(n);
  }
  return static_cast<ssize_t>(sent);
}

bool Connection::readable() const {
  return consumed_ < buffer_.size() || poll_for(fd_, POLLIN, static_cast<int>(read_timeout_.count()));
}
bool Connection::writable() const { return poll_for(fd_, POLLOUT, static_cast<int>(write_timeout_.count())); }

// ---- the front ------------------------------------------------------------------------------------

struct ConnectionFront::Impl {
  struct Conn {
    Connection c;
    enum class State { Waiting, Ready, Busy, Returned } state = State::Waiting;
    Clock::time_point deadline;
    bool idle = true;            // no byte of the next request yet: a timeout closes silently
    std::size_t served = 0;      // requests answered on it
    std::size_t reserved = 0;    // prebuffer bytes held for its body
    std::size_t need = 0;        // with a reserved body: the bytes of head and body
    bool peer_closed = false;    // the client has sent all it will (FIN): answer, then close
  };
  struct Client {
    std::size_t open = 0, busy = 0;
  };

  Impl(FrontOptions o, Handler h) : options(std::move(o)), handler(std::move(h)) {
    if (options.workers == 0) options.workers = 1;
    if (options.max_busy_per_client == 0) options.max_busy_per_client = std::max<std::size_t>(1, options.workers - 1);
  }

  FrontOptions options;
  Handler handler;
  int listen_fd = -1, epoll_fd = -1, wake_fd = -1;
  std::atomic<bool> running{false}, stopping{false};

  mutable std::mutex mutex;
  std::condition_variable work;
  std::map<Conn*, std::unique_ptr<Conn>> conns;  // every open connection
  std::map<std::string, Client> clients;         // by IP address
  std::deque<Conn*> ready;                       // complete requests for the workers
  std::vector<Conn*> returned;                   // back from a worker: keep-alive
  std::size_t prebuffered = 0;                   // bytes reserved for bodies in the loop
  std::size_t busy = 0, refused = 0, timed_out = 0;
  bool workers_stop = false;

  // The loop's thread.
  void accept_all();
  void on_readable(Conn* conn);
  // What a waiting connection's bytes make it. Once Handed or Closed, `conn` is no longer the
  // loop's: a worker may already have answered and freed it.
  enum class Step { Waiting, Handed, Closed };
  Step advance(Conn* conn);
  void take_returned();
  void expire_waiting();
  void close_waiting(Conn* conn, int status = 0, const char* reason = "", const char* code = "",
                     const std::string& message = "");
  void to_ready(Conn* conn);
  void watch(Conn* conn);
  // Workers.
  void work_loop();
  Conn* take_ready();
  void serve(Conn* conn);
  void close_locked(Conn* conn);
  void wake() {
    const std::uint64_t one = 1;
    [[maybe_unused]] const ssize_t n = ::write(wake_fd, &one, sizeof one);
  }
};

void ConnectionFront::Impl::watch(Conn* conn) {
  epoll_event ev{};
  ev.events = EPOLLIN | EPOLLRDHUP;
  ev.data.ptr = conn;
  ::epoll_ctl(epoll_fd, EPOLL_CTL_ADD, conn->c.fd_, &ev);
}

void ConnectionFront::Impl::accept_all() {
  for (;;) {
    sockaddr_storage peer{};
    socklen_t len = sizeof peer;
    const int fd = ::accept4(listen_fd, reinterpret_cast<sockaddr*>(&peer), &len, SOCK_NONBLOCK | SOCK_CLOEXEC);
    if (fd < 0) {
      if (errno == EINTR) continue;
      if (errno == EMFILE || errno == ENFILE) std::this_thread::sleep_for(milliseconds(5));  // let some close
      return;
    }
    int yes = 1;
    ::setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &yes, sizeof yes);
    auto [ip, port] = address_text(peer);
    std::unique_lock lock(mutex);
    Client& client = clients[ip];
    if (conns.size() >= options.max_connections || client.open >= options.max_connections_per_client) {
      const bool per_client = conns.size() < options.max_connections;
      if (client.open == 0) clients.erase(ip);
      ++refused;
      lock.unlock();
      answer_and_close(fd, 503, "Service Unavailable", "too_many_connections",
                       per_client ? "this client has " + std::to_string(options.max_connections_per_client) +
                                        " connections open, the limit (--max-connections-per-client)"
                                  : "the server has " + std::to_string(options.max_connections) +
                                        " connections open, the limit (--max-connections)");
      continue;
    }
    ++client.open;
    auto conn = std::make_unique<Conn>();
    Conn* raw = conn.get();
    raw->c.fd_ = fd;
    raw->c.remote_ip_ = ip;
    raw->c.remote_port_ = port;
    sockaddr_storage local{};
    socklen_t local_len = sizeof local;
    if (::getsockname(fd, reinterpret_cast<sockaddr*>(&local), &local_len) == 0)
      std::tie(raw->c.local_ip_, raw->c.local_port_) = address_text(local);
    raw->c.read_timeout_ = options.read_timeout;
    raw->c.write_timeout_ = options.write_timeout;
    raw->c.min_rate_ = options.min_body_rate;
    raw->c.grace_ = options.request_timeout;
    raw->deadline = Clock::now() + options.request_timeout;  // a new connection owes its first request
    conns.emplace(raw, std::move(conn));
    lock.unlock();
    watch(raw);
  }
}

void ConnectionFront::Impl::on_readable(Conn* conn) {
  Connection& c = conn->c;
  char buf[16384];
  bool eof = false;
  // Read no more than the head limit, or the prebuffered body's end (and a byte to see the head's).
  for (;;) {
    const std::size_t cap = std::max(options.max_header_bytes, conn->need);
    if (c.buffer_.size() >= cap + 1) break;
    const ssize_t n = ::recv(c.fd_, buf, std::min(sizeof buf, cap + 1 - c.buffer_.size()), 0);
    if (n > 0) {
      if (conn->idle) {  // the first byte of a request starts its deadline
        conn->idle = false;
        conn->deadline = Clock::now() + options.request_timeout;
      }
      c.buffer_.append(buf, static_cast<std::size_t>(n));
      continue;
    }
    if (n < 0 && errno == EINTR) continue;
    eof = n == 0 || (errno != EAGAIN && errno != EWOULDBLOCK);
    break;
  }
  if (eof) conn->peer_closed = true;
  // A client that half-closed after a complete request is answered; anything less is closed.
  if (advance(conn) == Step::Waiting && eof) close_waiting(conn);
}

ConnectionFront::Impl::Step ConnectionFront::Impl::advance(Conn* conn) {
  Connection& c = conn->c;
  const Head head = parse_head(c.buffer_, options.max_header_bytes);
  if (head.kind == Head::Kind::Incomplete) return Step::Waiting;
  if (head.kind == Head::Kind::TooLarge) {
    close_waiting(conn, 431, "Request Header Fields Too Large", "headers_too_large",
                  "the request line and headers exceed " + std::to_string(options.max_header_bytes) + " bytes");
    return Step::Closed;
  }
  const std::size_t body = head.length.value_or(0);
  if (head.other_body || body == 0 || body > options.prebuffer_body_bytes) {
    to_ready(conn);
    return Step::Handed;
  }
  if (conn->reserved == 0) {
    std::lock_guard lock(mutex);
    if (prebuffered + body > options.prebuffer_total_bytes) {
      // The loop's budget is taken: the worker reads this body, at the minimum rate.
    } else {
      prebuffered += body;
      conn->reserved = body;
      conn->need = head.end + body;
      // The body's own time, at the minimum rate, on top of the head's deadline.
      conn->deadline += std::chrono::duration_cast<Clock::duration>(
          std::chrono::duration<double>(static_cast<double>(body) / std::max(1.0, options.min_body_rate)));
    }
  }
  if (conn->reserved != 0 && c.buffer_.size() < head.end + body) return Step::Waiting;
  to_ready(conn);
  return Step::Handed;
}

void ConnectionFront::Impl::to_ready(Conn* conn) {
  ::epoll_ctl(epoll_fd, EPOLL_CTL_DEL, conn->c.fd_, nullptr);
  {
    std::lock_guard lock(mutex);
    prebuffered -= conn->reserved;
    conn->reserved = 0;
    conn->need = 0;
    conn->state = Conn::State::Ready;
    ready.push_back(conn);
  }
  work.notify_all();
}

void ConnectionFront::Impl::close_waiting(Conn* conn, int status, const char* reason, const char* code,
                                          const std::string& message) {
  const int fd = conn->c.fd_;
  ::epoll_ctl(epoll_fd, EPOLL_CTL_DEL, fd, nullptr);
  {
    std::lock_guard lock(mutex);
    prebuffered -= conn->reserved;
    conn->reserved = 0;
    conn->c.fd_ = -1;  // closed below, after the answer
    close_locked(conn);
  }
  if (status == 0) {
    ::close(fd);
  } else {
    answer_and_close(fd, status, reason, code, message);
  }
}

// Connections that missed their deadline: silently closed when idle, answered 408 when a request
// had begun.
void ConnectionFront::Impl::expire_waiting() {
  const auto now = Clock::now();
  std::vector<Conn*> late;
  {
    std::lock_guard lock(mutex);
    for (const auto& [raw, conn] : conns)
      if (raw->state == Conn::State::Waiting && raw->deadline <= now) late.push_back(raw);
    timed_out += late.size();
  }
  for (Conn* conn : late) {
    if (conn->idle)
      close_waiting(conn);
    else
      close_waiting(conn, 408, "Request Timeout", "request_timeout",
                    "the request did not arrive within " + std::to_string(options.request_timeout.count() / 1000) +
                        " s (--request-timeout-s)");
  }
}

void ConnectionFront::Impl::take_returned() {
  std::uint64_t count = 0;
  [[maybe_unused]] const ssize_t n = ::read(wake_fd, &count, sizeof count);
  std::vector<Conn*> back;
  {
    std::lock_guard lock(mutex);
    back.swap(returned);
    for (Conn* conn : back) conn->state = Conn::State::Waiting;
  }
  for (Conn* conn : back) {
    conn->idle = conn->c.consumed_ >= conn->c.buffer_.size();
    conn->c.buffer_.erase(0, conn->c.consumed_);
    conn->c.consumed_ = 0;
    conn->deadline = Clock::now() + (conn->idle ? options.keep_alive_timeout : options.request_timeout);
    watch(conn);
    if (!conn->idle) advance(conn);  // a pipelined request may be complete already
  }
}

void ConnectionFront::Impl::close_locked(Conn* conn) {
  if (conn->c.fd_ >= 0) ::close(conn->c.fd_);
  const auto it = clients.find(conn->c.remote_ip_);
  if (it != clients.end() && --it->second.open == 0 && it->second.busy == 0) clients.erase(it);
  conns.erase(conn);
}

// ---- workers --------------------------------------------------------------------------------------

// The oldest ready request whose client holds fewer than max_busy_per_client workers.
ConnectionFront::Impl::Conn* ConnectionFront::Impl::take_ready() {
  std::unique_lock lock(mutex);
  for (;;) {
    if (workers_stop) return nullptr;
    for (auto it = ready.begin(); it != ready.end(); ++it) {
      Client& client = clients[(*it)->c.remote_ip_];
      if (client.busy >= options.max_busy_per_client) continue;
      Conn* conn = *it;
      ready.erase(it);
      ++client.busy;
      ++busy;
      conn->state = Conn::State::Busy;
      return conn;
    }
    work.wait(lock);
  }
}

void ConnectionFront::Impl::serve(Conn* conn) {
  Connection& c = conn->c;
  c.request_start_ = Clock::now();
  c.read_from_socket_ = 0;
  const bool last = conn->served + 1 >= options.max_requests_per_connection || stopping;
  bool close = false;
  bool ok = false;
  try {
    ok = handler(c, last, close);
  } catch (...) {
    ok = false;  // the handler answers its own errors; anything else ends the connection
  }
  ++conn->served;
  std::unique_lock lock(mutex);
  --busy;
  Client& client = clients[c.remote_ip_];
  --client.busy;
  if (!ok || close || last || stopping || conn->peer_closed) {
    close_locked(conn);
  } else {
    conn->state = Conn::State::Returned;  // the loop's again once it has taken it back
    returned.push_back(conn);
    wake();
  }
  lock.unlock();
  work.notify_all();  // a client below its busy limit again may have requests waiting
}

void ConnectionFront::Impl::work_loop() {
  while (Conn* conn = take_ready()) serve(conn);
}

// ---- the public side ---------------------------------------------------------------------------------

ConnectionFront::ConnectionFront(FrontOptions options, Handler handler)
    : impl_(std::make_unique<Impl>(std::move(options), std::move(handler))) {}

ConnectionFront::~ConnectionFront() {
  stop();
  if (impl_->listen_fd >= 0) ::close(impl_->listen_fd);
}

int ConnectionFront::bind(const std::string& host, int port) {
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_STREAM;
  hints.ai_flags = AI_PASSIVE | AI_NUMERICSERV;
  addrinfo* found = nullptr;
  if (::getaddrinfo(host.c_str(), std::to_string(port).c_str(), &hints, &found) != 0) return -1;
  int fd = -1;
  for (addrinfo* a = found; a && fd < 0; a = a->ai_next) {
    fd = ::socket(a->ai_family, a->ai_socktype | SOCK_CLOEXEC | SOCK_NONBLOCK, a->ai_protocol);
    if (fd < 0) continue;
    // SO_REUSEADDR, not SO_REUSEPORT: a second server on the same port fails to start instead of
    // silently sharing the traffic.
    int yes = 1;
    ::setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
    if (::bind(fd, a->ai_addr, a->ai_addrlen) != 0 || ::listen(fd, SOMAXCONN) != 0) {
      ::close(fd);
      fd = -1;
    }
  }
  ::freeaddrinfo(found);
  if (fd < 0) return -1;
  sockaddr_storage bound{};
  socklen_t len = sizeof bound;
  ::getsockname(fd, reinterpret_cast<sockaddr*>(&bound), &len);
  impl_->listen_fd = fd;
  return address_text(bound).second;
}

bool ConnectionFront::run() {
  Impl& s = *impl_;
  if (s.listen_fd < 0 || s.stopping) return false;
  s.epoll_fd = ::epoll_create1(EPOLL_CLOEXEC);
  s.wake_fd = ::eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC);
  epoll_event ev{};
  ev.events = EPOLLIN;
  ev.data.ptr = &s.listen_fd;
  ::epoll_ctl(s.epoll_fd, EPOLL_CTL_ADD, s.listen_fd, &ev);
  ev.data.ptr = &s.wake_fd;
  ::epoll_ctl(s.epoll_fd, EPOLL_CTL_ADD, s.wake_fd, &ev);
  std::vector<std::thread> workers;
  for (std::size_t k = 0; k < s.options.workers; ++k) workers.emplace_back([&s] { s.work_loop(); });
  s.running = true;

  epoll_event events[64];
  auto next_sweep = Clock::now();
  while (!s.stopping) {
    const int n = ::epoll_wait(s.epoll_fd, events, 64, 100);
    for (int k = 0; k < n && !s.stopping; ++k) {
      void* who = events[k].data.ptr;
      if (who == &s.listen_fd) s.accept_all();
      else if (who == &s.wake_fd) s.take_returned();
      else s.on_readable(static_cast<Impl::Conn*>(who));
    }
    if (Clock::now() >= next_sweep) {
      s.expire_waiting();
      next_sweep = Clock::now() + milliseconds(100);
    }
  }

  // Stop: no new connections, the waiting ones closed, the busy ones' reads ended so that their
  // workers answer and finish.
  ::close(s.listen_fd);
  s.listen_fd = -1;
  {
    std::lock_guard lock(s.mutex);
    s.workers_stop = true;
    for (const auto& [raw, conn] : s.conns)
      if (raw->state == Impl::Conn::State::Busy) ::shutdown(raw->c.fd_, SHUT_RD);
  }
  s.work.notify_all();
  for (auto& t : workers) t.join();
  {
    std::lock_guard lock(s.mutex);
    while (!s.conns.empty()) s.close_locked(s.conns.begin()->first);
    s.ready.clear();
    s.returned.clear();
  }
  ::close(s.epoll_fd);
  ::close(s.wake_fd);
  s.running = false;
  return true;
}

void ConnectionFront::stop() {
  impl_->stopping = true;
  if (impl_->wake_fd >= 0) impl_->wake();
}

bool ConnectionFront::is_running() const { return impl_->running; }

ConnectionFront::Counts ConnectionFront::counts() const {
  std::lock_guard lock(impl_->mutex);
  Counts c;
  c.open = impl_->conns.size();
  c.busy = impl_->busy;
  c.waiting = c.open - c.busy - impl_->ready.size();
  c.refused = impl_->refused;
  c.timed_out = impl_->timed_out;
  return c;
}

}  // namespace lambert
