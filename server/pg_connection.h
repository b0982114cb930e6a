// A small C++ face of libpq, the PostgreSQL client library (the only file that includes it is
// pg_connection.cpp): connections, parameterised statements, results, transactions and a pool.
//
// Parameters travel separately from the SQL text (PQexecParams), never spliced into it. Text
// parameters are sent as text; bytes (scenes, results) in binary format, so a result of N bytes
// costs N bytes on the wire, not the 2N of bytea's hex text. A statement's results come as text,
// or all in binary format (Format::Binary) where a column holds bytes.
#pragma once

#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace lambert::pg {

// A failed statement or connection. `sqlstate` is PostgreSQL's five-character code ("23503": a
// foreign key violation, "23505": a unique violation), empty when the connection failed.
class Error : public std::runtime_error {
 public:
  Error(const std::string& message, std::string sqlstate)
      : std::runtime_error(message), sqlstate_(std::move(sqlstate)) {}
  const std::string& sqlstate() const { return sqlstate_; }

 private:
  std::string sqlstate_;
};

// One parameter: text, bytes (binary bytea), or SQL NULL.
struct Param {
  enum class Kind { Text, Bytes, Null } kind = Kind::Null;
  std::string value;
  static Param text(std::string v) { return {Kind::Text, std::move(v)}; }
  static Param bytes(std::string_view v) { return {Kind::Bytes, std::string(v)}; }
  static Param null() { return {}; }
};
// Numbers as text parameters, written so that PostgreSQL reads back the same value.
Param number(double v);
Param number(std::int64_t v);

enum class Format { Text, Binary };

// The rows a statement returned (or none), and how many rows it changed.
class Rows {
 public:
  Rows() = default;
  Rows(void* result, Format format);  // takes a PGresult
  ~Rows();
  Rows(Rows&& other) noexcept;
  Rows& operator=(Rows&& other) noexcept;

  int size() const;
  std::size_t changed() const;  // rows inserted, updated or deleted
  bool is_null(int row, int col) const;
  // Text results: the value's text. Binary results: text and bytea columns' bytes.
  std::string text(int row, int col) const;
  std::int64_t integer(int row, int col) const;   // int8 (text or binary)
  double real(int row, int col) const;            // float8 (text or binary)
  bool boolean(int row, int col) const;           // bool (text or binary)

 private:
  void* result_ = nullptr;  // PGresult*
  Format format_ = Format::Text;
};

class Connection {
 public:
  explicit Connection(const std::string& conninfo);  // throws Error
  ~Connection();
  Connection(const Connection&) = delete;
  Connection& operator=(const Connection&) = delete;

  // Several statements may be given only without parameters (and then results come as text).
  Rows exec(const std::string& sql, const std::vector<Param>& params = {}, Format format = Format::Text);
  bool healthy() const;
  void reset();  // reconnects (after a broken connection); throws Error
  // "database D on HOST:PORT", without credentials.
  std::string describe() const;

 private:
  void* conn_ = nullptr;  // PGconn*
};

// Runs `body(connection)` between BEGIN and COMMIT; a thrown exception rolls back and propagates.
template <typename Body>
auto in_transaction(Connection& c, Body&& body) {
  c.exec("BEGIN");
  try {
    if constexpr (std::is_void_v<decltype(body(c))>) {
      body(c);
      c.exec("COMMIT");
    } else {
      auto out = body(c);
      c.exec("COMMIT");
      return out;
    }
  } catch (...) {
    if (c.healthy()) {
      try {
        c.exec("ROLLBACK");
      } catch (...) {
      }
    }
    throw;
  }
}

// Up to `max_connections` connections, opened when first needed and reopened when broken. lease()
// waits while all are in use.
class Pool {
 public:
  Pool(std::string conninfo, std::size_t max_connections);
  ~Pool();

  class Lease {
   public:
    Lease(Pool& pool, std::unique_ptr<Connection> c) : pool_(&pool), c_(std::move(c)) {}
    Lease(Lease&& o) noexcept : pool_(o.pool_), c_(std::move(o.c_)) {}
    ~Lease() { if (c_) pool_->give_back(std::move(c_)); }
    Connection& operator*() { return *c_; }
    Connection* operator->() { return c_.get(); }

   private:
    Pool* pool_;
    std::unique_ptr<Connection> c_;
  };
  Lease lease();

 private:
  void give_back(std::unique_ptr<Connection> c);
  std::string conninfo_;
  std::size_t max_, open_ = 0;
  std::mutex mutex_;
  std::condition_variable free_cv_;
  std::vector<std::unique_ptr<Connection>> idle_;
};

}  // namespace lambert::pg
