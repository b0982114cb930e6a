// A throw-away PostgreSQL cluster for the tests that need one (tools/pg-throwaway.sh): the one ctest
// started for all of them (LAMBERT_TEST_PG_URI), or, for a test program run by hand, one started on
// first use, listening only on a Unix socket in its own temporary directory, stopped and removed
// when the test program exits. The README's test command installs `postgresql`, so these tests never
// skip: a cluster that cannot start fails them.
#pragma once

#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "server/job_store.h"
#include "server/pg_connection.h"

namespace lambert {

class PgCluster {
 public:
  static PgCluster& get() {
    static PgCluster cluster;
    return cluster;
  }
  bool ok() const { return !uri_.empty(); }
  const std::string& error() const { return error_; }

  // A new, empty database of its own for one test, as a connection URI.
  std::string fresh_database() {
    const std::string name = "lambert_test_" + JobStore::new_id().substr(0, 12);
    pg::Connection admin(uri_);
    admin.exec("CREATE DATABASE " + name);
    return database_uri(name);
  }
  std::string database_uri(const std::string& name) const {
    std::string uri = uri_;
    uri.replace(uri.find("/postgres?"), 10, "/" + name + "?");
    return uri;
  }

 private:
  PgCluster() {
    // Under ctest one cluster serves every test (the lambert_pg fixture in tests/CMakeLists.txt).
    if (const char* shared = std::getenv("LAMBERT_TEST_PG_URI")) {
      uri_ = shared;
      return;
    }
    dir_ = (std::filesystem::temp_directory_path() / ("lambert-pg-" + JobStore::new_id().substr(0, 10))).string();
    const std::string command = std::string(LAMBERT_SOURCE_DIR) + "/tools/pg-throwaway.sh start " + dir_ + " 2>&1";
    FILE* p = ::popen(command.c_str(), "r");
    std::string out;
    char buf[512];
    while (p && std::fgets(buf, sizeof buf, p)) out += buf;
    const int status = p ? ::pclose(p) : -1;
    while (!out.empty() && out.back() == '\n') out.pop_back();
    if (status == 0 && out.rfind("postgresql://", 0) == 0) uri_ = out;
    else error_ = "tools/pg-throwaway.sh could not start a cluster: " + out;
  }
  ~PgCluster() {
    if (dir_.empty()) return;
    const std::string command = std::string(LAMBERT_SOURCE_DIR) + "/tools/pg-throwaway.sh stop " + dir_;
    if (std::system(command.c_str()) != 0) std::fprintf(stderr, "could not stop the cluster in %s\n", dir_.c_str());
  }
  std::string dir_, uri_, error_;
};

// The URI of a fresh database, or a fatal failure of the calling test.
#define LAMBERT_FRESH_DATABASE(uri)                                   \
  ASSERT_TRUE(PgCluster::get().ok()) << PgCluster::get().error();    \
  const std::string uri = PgCluster::get().fresh_database()

}  // namespace lambert
