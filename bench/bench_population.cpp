// bench_population: throughput of scripts/population.sh (docs/population.md) on this machine. Runs
// one small population (default 10 encounters, seed 1, plus its runs without humans) with -j =
// cores, then the same runs one at a time, in one process, and prints the wall times, whether the
// two population.json files are identical (they must be: the runs are in lockstep and seeded), and
// RESULT lines: encounters per hour at -j = cores (wall time of the whole population, runs
// without humans included) and the speed-up of -j = cores over -j 1.
//   COOPNAV_BENCH_POP_N: number of encounters (default 10).
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>

#include "bench_util.hpp"

namespace {

const std::string kSource = COOPNAV_SOURCE_DIR;
const std::string kBuild = COOPNAV_BINARY_DIR;

std::string readFile(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  std::ostringstream s;
  s << f.rdbuf();
  return s.str();
}

struct Outcome {
  double wall_s = 0.0;
  int exit_code = -1;
};

Outcome runPopulation(int n, int jobs, const std::string& out, int port_base) {
  ::setenv("COOPNAV_BUILD_DIR", kBuild.c_str(), 1);
  ::setenv("COOPNAV_POP_PORT_BASE", std::to_string(port_base).c_str(), 1);
  const auto t0 = std::chrono::steady_clock::now();
  const pid_t pid = coopnav::bench::spawnProcess(
      {"/bin/bash", kSource + "/scripts/population.sh", "--no-build", "--n", std::to_string(n),
       "--seed", "1", "-j", std::to_string(jobs), "--out", out},
      out + ".log");
  int st = 0;
  ::waitpid(pid, &st, 0);
  Outcome o;
  o.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  o.exit_code = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  return o;
}

}  // namespace

int main() {
  const char* env_n = std::getenv("COOPNAV_BENCH_POP_N");
  const int n = env_n ? std::max(1, std::atoi(env_n)) : 10;
  const int cores = static_cast<int>(std::max(1L, ::sysconf(_SC_NPROCESSORS_ONLN)));
  const std::string dir = kBuild + "/bench_population";
  std::system(("rm -rf '" + dir + "' && mkdir -p '" + dir + "'").c_str());

  const Outcome par = runPopulation(n, cores, dir + "/parallel", 8300);
  const Outcome one = runPopulation(n, 1, dir + "/serial", 8300 + cores + 10);
  const std::string jobs_txt = readFile(dir + "/parallel/jobs.txt");
  long runs = 0;
  for (char c : jobs_txt) runs += c == '\n' ? 1 : 0;
  const bool same =
      readFile(dir + "/parallel/population.json") == readFile(dir + "/serial/population.json") &&
      !readFile(dir + "/serial/population.json").empty();
  std::printf("population of %d encounters (%ld runs with those without humans), seed 1\n", n,
              runs);
  std::printf("  -j %d: %.1f s wall (exit %d)\n", cores, par.wall_s, par.exit_code);
  std::printf("  -j 1: %.1f s wall (exit %d)\n", one.wall_s, one.exit_code);
  std::printf("  population.json of both identical: %s\n", same ? "yes" : "NO");
  std::printf("  logs: %s/{parallel,serial}.log\n", dir.c_str());
  std::printf("RESULT population_encounters_per_hour %.1f\n", n * 3600.0 / par.wall_s);
  std::printf("RESULT population_parallel_speedup %.3f\n", one.wall_s / par.wall_s);
  return same ? 0 : 1;
}
