// libpq behind pg_connection.h. Binary results are decoded by the column's type as PostgreSQL's
// send functions write them: int8 and float8 as 8 bytes big-endian, bool as one byte, text and
// bytea as their bytes.
#include "server/pg_connection.h"

#include <libpq-fe.h>

#include <charconv>
#include <cstring>

namespace lambert::pg {
namespace {

PGresult* as_result(void* r) { return static_cast<PGresult*>(r); }
PGconn* as_conn(void* c) { return static_cast<PGconn*>(c); }

std::string trimmed(const char* message) {
  std::string s = message ? message : "";
  while (!s.empty() && (s.back() == '\n' || s.back() == ' ')) s.pop_back();
  return s;
}

std::uint64_t big_endian(const char* p, int length) {
  std::uint64_t v = 0;
  for (int k = 0; k < length; ++k) v = (v << 8) | static_cast<unsigned char>(p[k]);
  return v;
}

}  // namespace

Param number(double v) {
  char buf[32];
  const auto [end, ec] = std::to_chars(buf, buf + sizeof buf, v);  // shortest exact form
  return Param::text(std::string(buf, end));
}
Param number(std::int64_t v) { return Param::text(std::to_string(v)); }

// ---- results --------------------------------------------------------------------------------------

Rows::Rows(void* result, Format format) : result_(result), format_(format) {}
Rows::~Rows() {
  if (result_) PQclear(as_result(result_));
}
Rows::Rows(Rows&& o) noexcept : result_(o.result_), format_(o.format_) { o.result_ = nullptr; }
Rows& Rows::operator=(Rows&& o) noexcept {
  if (this != &o) {
    if (result_) PQclear(as_result(result_));
    result_ = o.result_;
    format_ = o.format_;
    o.result_ = nullptr;
  }
  return *this;
}

int Rows::size() const { return result_ ? PQntuples(as_result(result_)) : 0; }

std::size_t Rows::changed() const {
  if (!result_) return 0;
  const char* n = PQcmdTuples(as_result(result_));
  return n && *n ? std::stoul(n) : 0;
}

bool Rows::is_null(int row, int col) const { return PQgetisnull(as_result(result_), row, col) != 0; }

std::string Rows::text(int row, int col) const {
  const PGresult* r = as_result(result_);
  return std::string(PQgetvalue(r, row, col), static_cast<std::size_t>(PQgetlength(r, row, col)));
}

std::int64_t Rows::integer(int row, int col) const {
  const PGresult* r = as_result(result_);
  if (format_ == Format::Binary) {
    if (PQgetlength(r, row, col) != 8) throw Error("expected an int8 column", "");
    return static_cast<std::int64_t>(big_endian(PQgetvalue(r, row, col), 8));
  }
  return std::stoll(PQgetvalue(r, row, col));
}

double Rows::real(int row, int col) const {
  const PGresult* r = as_result(result_);
  if (format_ == Format::Binary) {
    if (PQgetlength(r, row, col) != 8) throw Error("expected a float8 column", "");
    const std::uint64_t bits = big_endian(PQgetvalue(r, row, col), 8);
    double v;
    std::memcpy(&v, &bits, sizeof v);
    return v;
  }
  return std::stod(PQgetvalue(r, row, col));
}

bool Rows::boolean(int row, int col) const {
  const char* v = PQgetvalue(as_result(result_), row, col);
  return format_ == Format::Binary ? v[0] != 0 : v[0] == 't';
}

// ---- connections ----------------------------------------------------------------------------------

Connection::Connection(const std::string& conninfo) {
  conn_ = PQconnectdb(conninfo.c_str());
  if (!conn_ || PQstatus(as_conn(conn_)) != CONNECTION_OK) {
    const std::string message = conn_ ? trimmed(PQerrorMessage(as_conn(conn_))) : "out of memory";
    if (conn_) PQfinish(as_conn(conn_));
    conn_ = nullptr;
    throw Error("cannot connect to PostgreSQL: " + message, "");
  }
  // Notices ("relation already exists, skipping") are not errors; keep them out of the log.
  PQsetNoticeProcessor(as_conn(conn_), [](void*, const char*) {}, nullptr);
}

Connection::~Connection() {
  if (conn_) PQfinish(as_conn(conn_));
}

bool Connection::healthy() const { return conn_ && PQstatus(as_conn(conn_)) == CONNECTION_OK; }

void Connection::reset() {
  PQreset(as_conn(conn_));
  if (!healthy()) throw Error("cannot reconnect to PostgreSQL: " + trimmed(PQerrorMessage(as_conn(conn_))), "");
}

std::string Connection::describe() const {
  const char* host = PQhost(as_conn(conn_));
  const std::string where = host && host[0] == '/' ? std::string("socket in ") + host
                                                   : std::string(host ? host : "?") + ":" + PQport(as_conn(conn_));
  return std::string("database ") + PQdb(as_conn(conn_)) + " on " + where;
}

Rows Connection::exec(const std::string& sql, const std::vector<Param>& params, Format format) {
  std::vector<const char*> values(params.size());
  std::vector<int> lengths(params.size()), formats(params.size());
  for (std::size_t k = 0; k < params.size(); ++k) {
    const Param& p = params[k];
    values[k] = p.kind == Param::Kind::Null ? nullptr : p.value.data();
    lengths[k] = static_cast<int>(p.value.size());
    formats[k] = p.kind == Param::Kind::Bytes ? 1 : 0;
  }
  // Without parameters: PQexec, which also runs several statements (the schema's migrations).
  PGresult* r = params.empty() && format == Format::Text
                    ? PQexec(as_conn(conn_), sql.c_str())
                    : PQexecParams(as_conn(conn_), sql.c_str(), static_cast<int>(params.size()), nullptr,
                                   values.data(), lengths.data(), formats.data(), format == Format::Binary ? 1 : 0);
  Rows rows(r, format);
  const ExecStatusType status = r ? PQresultStatus(r) : PGRES_FATAL_ERROR;
  if (status == PGRES_COMMAND_OK || status == PGRES_TUPLES_OK) return rows;
  const char* state = r ? PQresultErrorField(r, PG_DIAG_SQLSTATE) : nullptr;
  const std::string message = r ? trimmed(PQresultErrorMessage(r)) : trimmed(PQerrorMessage(as_conn(conn_)));
  throw Error("PostgreSQL: " + (message.empty() ? trimmed(PQerrorMessage(as_conn(conn_))) : message),
              state ? state : "");
}

// ---- the pool -------------------------------------------------------------------------------------

Pool::Pool(std::string conninfo, std::size_t max_connections)
    : conninfo_(std::move(conninfo)), max_(std::max<std::size_t>(1, max_connections)) {}

Pool::~Pool() = default;

Pool::Lease Pool::lease() {
  std::unique_ptr<Connection> c;
  {
    std::unique_lock lock(mutex_);
    free_cv_.wait(lock, [&] { return !idle_.empty() || open_ < max_; });
    if (!idle_.empty()) {
      c = std::move(idle_.back());
      idle_.pop_back();
    } else {
      ++open_;  // opened below, outside the lock (a network round trip)
    }
  }
  try {
    if (!c) c = std::make_unique<Connection>(conninfo_);
    else if (!c->healthy()) c->reset();
  } catch (...) {
    std::lock_guard lock(mutex_);
    --open_;
    free_cv_.notify_one();
    throw;
  }
  return Lease(*this, std::move(c));
}

void Pool::give_back(std::unique_ptr<Connection> c) {
  std::lock_guard lock(mutex_);
  idle_.push_back(std::move(c));
  free_cv_.notify_one();
}

}  // namespace lambert::pg
