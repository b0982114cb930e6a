// The HTTP service's accept path (issue 37: eight connections trickling their headers at one byte per
// 0.5 s held all eight connection threads, and /v1/health timed out for as long as they lasted).
//
// Every connection first waits in one epoll loop, which holds no worker: it is accepted there, its
// request line and headers are read there, under a deadline for the whole of them (not per read, so
// a trickle does not keep it alive), and a body of up to `prebuffer_body_bytes` is read there too.
// Only a complete request goes to a worker thread, and an idle keep-alive connection goes back to
// the loop. On top of that:
//   - a client (an IP address) may keep at most `max_connections_per_client` connections open and
//     occupy at most `max_busy_per_client` workers (by default all but one: another client always
//     finds the last worker free);
//   - at most `max_connections` connections are open at all; beyond either limit a new connection
//     is answered 503 and closed at once;
//   - a body that a worker reads (a large one) must keep up `min_body_rate` bytes/s after a grace of
//     `request_timeout`, or the read fails (the service answers 400 and closes).
// Requests that miss their deadline are answered 408, headers beyond `max_header_bytes` 431.
//
// No HTTP parsing beyond finding the end of the headers and Content-Length / Transfer-Encoding /
// Expect: a worker's Connection is handed to the `Handler`, which parses and answers the request
// (server/http_server.cpp, cpp-httplib's request processing).
#pragma once

#include <sys/types.h>

#include <chrono>
#include <cstddef>
#include <functional>
#include <memory>
#include <string>

namespace lambert {

struct FrontOptions {
  std::size_t workers = 8;                       // requests handled at once
  std::size_t max_connections = 512;             // open connections in all
  std::size_t max_connections_per_client = 64;   // open connections of one IP address
  std::size_t max_busy_per_client = 0;           // workers one IP address may hold; 0: workers − 1
  std::chrono::milliseconds request_timeout{10000};    // request line and headers (and a prebuffered body)
  std::chrono::milliseconds keep_alive_timeout{5000};  // idle between two requests
  std::chrono::milliseconds read_timeout{30000};   // a worker's wait for the next bytes of a body
  std::chrono::milliseconds write_timeout{30000};  // a worker's wait to write the next bytes
  std::size_t max_header_bytes = 64 << 10;       // request line and headers
  std::size_t prebuffer_body_bytes = 1 << 20;    // bodies up to this size are read before a worker
  std::size_t prebuffer_total_bytes = 64 << 20;  // all bodies being prebuffered at once
  double min_body_rate = 16 << 10;               // bytes/s a worker's body read must keep up
  std::size_t max_requests_per_connection = 100;
};

// One connection while a worker handles a request on it: the bytes already read, then the socket.
class Connection {
 public:
  // Reads what is buffered, else waits for the socket (read_timeout per read, and the body's rate):
  // > 0 bytes, 0 at the end of the stream, -1 on a timeout or an error.
  ssize_t read(char* data, std::size_t size);
  // Writes all of it (write_timeout per wait); the count, or -1.
  ssize_t write(const char* data, std::size_t size);
  bool readable() const;  // bytes buffered, or the socket readable within read_timeout
  bool writable() const;
  int fd() const { return fd_; }
  const std::string& remote_ip() const { return remote_ip_; }
  int remote_port() const { return remote_port_; }
  const std::string& local_ip() const { return local_ip_; }
  int local_port() const { return local_port_; }

 private:
  friend class ConnectionFront;
  int fd_ = -1;
  std::string remote_ip_, local_ip_;
  int remote_port_ = 0, local_port_ = 0;
  std::string buffer_;          // read from the socket, not yet consumed
  std::size_t consumed_ = 0;    // of buffer_
  std::chrono::milliseconds read_timeout_{30000}, write_timeout_{30000};
  double min_rate_ = 0;         // bytes/s once the grace is over; 0: none
  std::chrono::milliseconds grace_{10000};
  std::chrono::steady_clock::time_point request_start_{};
  std::size_t read_from_socket_ = 0;  // during this request, by read()
};

class ConnectionFront {
 public:
  // Handles one request on `c`; `last` when the connection closes after it. Returns false, or sets
  // `close`, when the connection must not carry another request.
  using Handler = std::function<bool(Connection& c, bool last, bool& close)>;

  ConnectionFront(FrontOptions options, Handler handler);
  ~ConnectionFront();  // stop()
  ConnectionFront(const ConnectionFront&) = delete;
  ConnectionFront& operator=(const ConnectionFront&) = delete;

  // Binds host:port (port 0: any free one) and listens; the port, or -1.
  int bind(const std::string& host, int port);
  // Accepts and serves until stop(); false if it could not run (not bound).
  bool run();
  // Stops accepting, closes waiting connections and waits for the workers' current requests; safe
  // from another thread, not from a signal handler.
  void stop();
  bool is_running() const;

  struct Counts {
    std::size_t open = 0, waiting = 0, busy = 0, refused = 0, timed_out = 0;
  };
  Counts counts() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace lambert
