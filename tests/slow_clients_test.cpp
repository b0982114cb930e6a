// Slow or stalled connections cannot take the last worker (issue 37: eight connections trickling
// their headers at one byte per 0.5 s made /v1/health time out for as long as they lasted). Real
// sockets against the real server: the tricklers are threads writing a byte at a time, and the
// service must meanwhile answer another request at once. Clients are told apart by address: the
// whole of 127.0.0.0/8 is loopback, so a second client connects from 127.0.0.2.
#include <gtest/gtest.h>

#include <netinet/in.h>
#include <fcntl.h>
#include <poll.h>
#include <sys/resource.h>

#include <atomic>
#include <thread>
#include <vector>

#include "tests/service_fixture.h"

namespace lambert {
namespace {

// A TCP connection to the server from `from` (an address on the loopback), or -1.
int connect_from(int port, const char* from = "127.0.0.1") {
  const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  sockaddr_in local{};
  local.sin_family = AF_INET;
  ::inet_pton(AF_INET, from, &local.sin_addr);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(static_cast<uint16_t>(port));
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (::bind(fd, reinterpret_cast<sockaddr*>(&local), sizeof local) != 0 ||
      ::connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0) {
    ::close(fd);
    return -1;
  }
  return fd;
}

// Everything the server sends until it closes (then `*closed` is set) or `timeout` passes.
std::string read_all(int fd, std::chrono::milliseconds timeout, bool* closed = nullptr) {
  std::string out;
  const auto end = Clock::now() + timeout;
  char buf[4096];
  while (Clock::now() < end) {
    pollfd p{fd, POLLIN, 0};
    if (::poll(&p, 1, 50) <= 0) continue;
    const ssize_t n = ::recv(fd, buf, sizeof buf, 0);
    if (n <= 0) {
      if (closed) *closed = true;
      break;
    }
    out.append(buf, static_cast<std::size_t>(n));
  }
  return out;
}

// Sends `text` one byte every `gap`; counts in `answered` the moment the server answers (or closes)
// before the end, and returns what it answered.
std::string trickle(int fd, const std::string& text, std::chrono::milliseconds gap, std::atomic<int>& answered) {
  bool early = false;
  for (char c : text) {
    pollfd p{fd, POLLIN, 0};
    early = ::send(fd, &c, 1, MSG_NOSIGNAL) != 1 || ::poll(&p, 1, static_cast<int>(gap.count())) > 0;
    if (early) break;
  }
  if (early) ++answered;
  return read_all(fd, 100ms);
}

// GET /v1/health from `from` on a fresh connection: its status (-1: no answer within 10 s).
int health_from(int port, const char* from) {
  const int fd = connect_from(port, from);
  if (fd < 0) return -1;
  const std::string req = "GET /v1/health HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n";
  ::send(fd, req.data(), req.size(), MSG_NOSIGNAL);
  const std::string answer = read_all(fd, 10s);
  ::close(fd);
  return answer.empty() ? -1 : raw_status(answer);
}

// Tricklers from 127.0.0.1, each sending `head` at once and then `slow` one byte per 0.5 s. After
// `settle`, health is asked `rounds` times from `from`. The claim is causal, not timed: every health
// request must be answered 200 while no trickler has been answered yet, i.e. while all of them still
// hold their connections (without the front, health waited for a trickler's timeout to free a
// worker). Returns how many health requests passed so, and through `told` what each trickler got.
int health_beside_tricklers(int port, int n, const std::string& head, const std::string& slow, const char* from,
                            std::chrono::milliseconds settle, int rounds, std::vector<std::string>& told) {
  std::atomic<int> answered{0};
  told.assign(n, "");
  std::vector<std::thread> threads;
  for (int k = 0; k < n; ++k)
    threads.emplace_back([&, k] {
      const int fd = connect_from(port);
      if (fd < 0) return;
      ::send(fd, head.data(), head.size(), MSG_NOSIGNAL);
      told[k] = trickle(fd, slow, 500ms, answered);
      ::close(fd);
    });
  std::this_thread::sleep_for(settle);  // every trickler connected and sending
  int passed = 0;
  for (int r = 0; r < rounds; ++r) {
    const int status = health_from(port, from);
    if (status == 200 && answered == 0) ++passed;
    std::this_thread::sleep_for(100ms);
  }
  for (auto& t : threads) t.join();
  return passed;
}

const std::string kSlowHead = "GET /v1/health HTTP/1.1\r\nHost: x\r\nX-Padding: " + std::string(200, 'a') + "\r\n\r\n";

TEST(SlowClients, HeaderTricklersHoldNoWorkerAndGet408) {
  HttpServerOptions http;
  http.request_timeout_s = 3;
  TestServer server(job_options(), http);
  std::vector<std::string> told;
  // The case, doubled: sixteen tricklers against eight workers, health from the same address.
  EXPECT_EQ(health_beside_tricklers(server.port(), 16, "", kSlowHead, "127.0.0.1", 500ms, 3, told), 3);
  // Each trickler had sent about 6 of its 250 bytes when its 3 s ran out.
  for (const std::string& t : told) {
    EXPECT_EQ(raw_status(t), 408) << t;
    EXPECT_EQ(raw_body(t)["error"]["code"], "request_timeout");
  }
}

TEST(SlowClients, SmallBodiesTrickledHoldNoWorker) {
  HttpServerOptions http;
  http.request_timeout_s = 2;
  TestServer server(job_options(), http);
  // The head at once, then 8 bytes of a 4000-byte body: it misses its deadline in the loop (408).
  const std::string head = "POST /v1/jobs HTTP/1.1\r\nHost: x\r\nContent-Type: application/json\r\nContent-Length: 4000\r\n\r\n";
  std::vector<std::string> told;
  EXPECT_EQ(health_beside_tricklers(server.port(), 12, head, std::string(8, ' '), "127.0.0.1", 300ms, 3, told), 3);
  for (const std::string& t : told) EXPECT_EQ(raw_status(t), 408) << t;
}

TEST(SlowClients, LargeBodiesTrickledCannotTakeTheLastWorker) {
  HttpServerOptions http;
  http.http_threads = 4;
  http.request_timeout_s = 2;  // also the grace before a body must keep up its minimum rate
  TestServer server(job_options(), http);
  // Bodies beyond the read-ahead go to workers; one address may hold all of them but one, so four
  // tricklers hold three workers and health from another address finds the fourth.
  const std::string head = "POST /v1/jobs HTTP/1.1\r\nHost: x\r\nContent-Length: 10000000\r\n\r\n";
  std::vector<std::string> told;
  EXPECT_EQ(health_beside_tricklers(server.port(), 4, head, std::string(20, ' '), "127.0.0.2", 300ms, 2, told), 2);
  // Past the grace, a body at 2 bytes/s falls below the minimum rate: 400, the connection closed.
  for (const std::string& t : told) {
    EXPECT_EQ(raw_status(t), 400) << t;
    EXPECT_EQ(raw_body(t)["error"]["code"], "invalid_body");
  }
}

TEST(SlowClients, ConnectionsPerClientAndInAllAreLimited) {
  HttpServerOptions http;
  http.max_connections_per_client = 20;
  http.max_connections = 30;
  TestServer server(job_options(), http);
  std::vector<int> held;
  for (int k = 0; k < 20; ++k) held.push_back(connect_from(server.port()));
  // The 21st connection of 127.0.0.1 is answered 503 and closed at once.
  const int extra = connect_from(server.port());
  const std::string refused = read_all(extra, 5s);
  ::close(extra);
  EXPECT_EQ(raw_status(refused), 503) << refused;
  EXPECT_EQ(raw_body(refused)["error"]["code"], "too_many_connections");
  EXPECT_NE(refused.find("Retry-After: 5"), std::string::npos);
  // Another client is served, and the server's own total holds too.
  EXPECT_EQ(health_from(server.port(), "127.0.0.2"), 200);
  for (int k = 0; k < 10; ++k) held.push_back(connect_from(server.port(), "127.0.0.3"));
  std::this_thread::sleep_for(200ms);
  EXPECT_EQ(health_from(server.port(), "127.0.0.4"), 503);
  for (int fd : held) ::close(fd);
  // Once they are closed, the first client is welcome again.
  for (int k = 0; k < 50 && health_from(server.port(), "127.0.0.1") != 200; ++k) std::this_thread::sleep_for(20ms);
  EXPECT_EQ(health_from(server.port(), "127.0.0.1"), 200);
}

TEST(SlowClients, PipelinedAndKeptAliveRequestsAreAnsweredInOrder) {
  TestServer server;
  const int fd = connect_from(server.port());
  const std::string two = "GET /v1/health HTTP/1.1\r\nHost: x\r\n\r\nGET /v1/nowhere HTTP/1.1\r\nHost: x\r\n\r\n";
  ::send(fd, two.data(), two.size(), MSG_NOSIGNAL);
  std::string answers = read_all(fd, 1500ms);
  const auto second = answers.find("HTTP/1.1 ", 1);
  ASSERT_NE(second, std::string::npos) << answers;
  EXPECT_EQ(raw_status(answers), 200);
  EXPECT_EQ(raw_status(answers.substr(second)), 404);
  // The same connection carries a third request after a pause (keep-alive).
  const std::string third = "GET /v1/health HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n";
  ::send(fd, third.data(), third.size(), MSG_NOSIGNAL);
  EXPECT_EQ(raw_status(read_all(fd, 5s)), 200);
  ::close(fd);
}

TEST(SlowClients, OversizedHeadsAre431AndIdleConnectionsAreClosed) {
  HttpServerOptions http;
  http.request_timeout_s = 1;
  http.keep_alive_timeout_s = 1;
  TestServer server(job_options(), http);
  const std::string huge = "GET /v1/health HTTP/1.1\r\nHost: x\r\nX-Big: " + std::string(100000, 'a') + "\r\n\r\n";
  const std::string r = raw_request(server.port(), huge);
  EXPECT_EQ(raw_status(r), 431) << r.substr(0, 300);
  EXPECT_EQ(raw_body(r)["error"]["code"], "headers_too_large");
  // A connection that never sends a byte is closed, without an answer, after the request timeout.
  const int silent = connect_from(server.port());
  bool closed = false;
  EXPECT_EQ(read_all(silent, 10s, &closed), "");
  EXPECT_TRUE(closed) << "still open after 10 s";
  ::close(silent);
}

// httplib built with select() answers 500 to a socket numbered FD_SETSIZE (1024) or more; the front
// hands httplib the real descriptor, so a busy server must still be served.
TEST(SlowClients, ASocketNumberedBeyondFdSetsizeIsServed) {
  rlimit limit{};
  ::getrlimit(RLIMIT_NOFILE, &limit);
  const rlimit before = limit;
  if (limit.rlim_cur < 1200) limit.rlim_cur = std::min<rlim_t>(1200, limit.rlim_max);
  ASSERT_EQ(::setrlimit(RLIMIT_NOFILE, &limit), 0);
  ASSERT_GE(limit.rlim_cur, 1200u) << "cannot open enough descriptors for this test";
  TestServer server;
  std::vector<int> filler;
  while (filler.size() < 1100) filler.push_back(::open("/dev/null", O_RDONLY | O_CLOEXEC));
  EXPECT_EQ(health_from(server.port(), "127.0.0.1"), 200);
  for (int fd : filler) ::close(fd);
  ::setrlimit(RLIMIT_NOFILE, &before);
}

}  // namespace
}  // namespace lambert
