// bench_population: what an encounter costs with scripts/population.sh (docs/population.md) on this
// machine, and where a run's wall time goes. Runs one small population (default 10 encounters,
// seed 1, plus its runs without humans) with -j JOBS and prints its wall time, encounters per
// core-hour (encounters over wall time x JOBS: the cores a cluster would give it, the runs without
// humans included), the CPU seconds of all its processes per encounter, and the breakdown of a
// run's wall time (python3 -m coopnav_exp.timing: run_one's phases, each daemon's time to ready)
// with the share that is simulation.
//   COOPNAV_BENCH_POP_N: encounters (default 10).  COOPNAV_BENCH_POP_JOBS: JOBS (default: cores).
//   COOPNAV_BENCH_POP_REFERENCE=SOURCE:BUILD: the same population with another checkout and its
//     build (e.g. main's, before a change), one run each in turn; its figures beside these, as
//     ratios, and whether both population.json are identical (they must be: same seed, same
//     tables, whatever the launcher). The reference's breakdown comes from its logs' stamps when
//     its runs write no timing.json.
//   COOPNAV_BENCH_POP_SERIAL=1: the population again at -j 1; identical tables and the speed-up.
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
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

double cpuOfChildren_s() {
  rusage u{};
  ::getrusage(RUSAGE_CHILDREN, &u);
  auto s = [](const timeval& t) { return static_cast<double>(t.tv_sec) + t.tv_usec / 1e6; };
  return s(u.ru_utime) + s(u.ru_stime);
}

struct Tree {
  std::string name, source, build;
};

struct Outcome {
  double wall_s = 0.0;
  double cpu_s = 0.0;  // every process of the population (reaped: their CPU is the children's)
  int exit_code = -1;
  std::string breakdown;                  // coopnav_exp.timing's text
  std::map<std::string, double> figures;  // its `key value` lines
};

Outcome runPopulation(const Tree& tree, int n, int jobs, const std::string& out, int port_base) {
  std::fflush(nullptr);  // a forked child must not write what this process has buffered
  ::setenv("COOPNAV_BUILD_DIR", tree.build.c_str(), 1);
  ::setenv("COOPNAV_POP_PORT_BASE", std::to_string(port_base).c_str(), 1);
  const double cpu0 = cpuOfChildren_s();
  const auto t0 = std::chrono::steady_clock::now();
  const pid_t pid = coopnav::bench::spawnProcess(
      {"/bin/bash", tree.source + "/scripts/population.sh", "--no-build", "--n", std::to_string(n),
       "--seed", "1", "-j", std::to_string(jobs), "--out", out},
      out + ".log");
  int st = 0;
  ::waitpid(pid, &st, 0);
  Outcome o;
  o.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  o.cpu_s = cpuOfChildren_s() - cpu0;
  o.exit_code = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  // This tree's reader of the timings, whichever tree ran the population.
  const std::string cmd = "PYTHONPATH='" + kSource + "/tools/exp' /usr/bin/python3 -m " +
                          "coopnav_exp.timing '" + out + "' 2>&1";
  std::fflush(nullptr);
  if (FILE* p = ::popen(cmd.c_str(), "r")) {
    std::array<char, 512> line{};
    while (std::fgets(line.data(), line.size(), p)) {
      const std::string l(line.data());
      o.breakdown += l;
      const auto sp = l.find(' ');
      if (sp != std::string::npos && l.find(' ', sp + 1) == std::string::npos)
        o.figures[l.substr(0, sp)] = std::atof(l.c_str() + sp + 1);
    }
    ::pclose(p);
  }
  return o;
}

void report(const char* label, const Tree& tree, int n, int jobs, const Outcome& o) {
  std::printf("%s (%s, build %s): %d encounters at -j %d in %.1f s wall (exit %d)\n", label,
              tree.source.c_str(), tree.build.c_str(), n, jobs, o.wall_s, o.exit_code);
  std::printf("  encounters per core-hour %.1f; CPU %.2f s per encounter (all processes)\n",
              n * 3600.0 / (o.wall_s * jobs), o.cpu_s / n);
  if (o.figures.count("worker_wall_sum_s"))
    std::printf(
        "  outside the runs' workers (generation, config checks, aggregation, slots idle at "
        "the end): %.1f of %.1f slot-seconds\n",
        o.wall_s * jobs - o.figures.at("worker_wall_sum_s"), o.wall_s * jobs);
  std::istringstream lines(o.breakdown);
  for (std::string l; std::getline(lines, l);)
    if (l.rfind("phase_mean_s.", 0) != 0) std::printf("  %s\n", l.c_str());
}

int envInt(const char* name, int fallback) {
  const char* v = std::getenv(name);
  return v ? std::max(1, std::atoi(v)) : fallback;
}

}  // namespace

int main() {
  const int n = envInt("COOPNAV_BENCH_POP_N", 10);
  const int cores = static_cast<int>(std::max(1L, ::sysconf(_SC_NPROCESSORS_ONLN)));
  const int jobs = envInt("COOPNAV_BENCH_POP_JOBS", cores);
  const std::string dir = kBuild + "/bench_population";
  std::system(("rm -rf '" + dir + "' && mkdir -p '" + dir + "'").c_str());
  const Tree self{"this tree", kSource, kBuild};

  const Outcome now = runPopulation(self, n, jobs, dir + "/this", 8300);
  const std::string table = readFile(dir + "/this/population.json");
  const std::string jobs_txt = readFile(dir + "/this/jobs.txt");
  const long runs = std::count(jobs_txt.begin(), jobs_txt.end(), '\n');
  std::printf("population of %d encounters (%ld runs with those without humans), seed 1\n", n,
              runs);
  report("this tree", self, n, jobs, now);
  bool same = !table.empty();

  const double per_core_hour = n * 3600.0 / (now.wall_s * jobs);
  const double share =
      now.figures.count("simulation_share") ? now.figures.at("simulation_share") : 0.0;
  std::printf("RESULT population_encounters_per_core_hour %.1f\n", per_core_hour);
  std::printf("RESULT population_encounters_per_hour %.1f\n", n * 3600.0 / now.wall_s);
  std::printf("RESULT population_cpu_s_per_encounter %.3f\n", now.cpu_s / n);
  std::printf("RESULT population_simulation_share %.4f\n", share);
  if (now.figures.count("run_wall_mean_s"))
    std::printf("RESULT population_run_wall_mean_s %.3f\n", now.figures.at("run_wall_mean_s"));
  for (const auto& [k, v] : now.figures)
    if (k.rfind("phase_mean_s.", 0) == 0) std::printf("RESULT population_%s %.4f\n", k.c_str(), v);

  if (const char* ref = std::getenv("COOPNAV_BENCH_POP_REFERENCE")) {
    const std::string r(ref);
    const auto colon = r.find(':');
    if (colon == std::string::npos) {
      std::fprintf(stderr, "COOPNAV_BENCH_POP_REFERENCE must be SOURCE:BUILD, not '%s'\n", ref);
      return 2;
    }
    const Tree other{"reference", r.substr(0, colon), r.substr(colon + 1)};
    const Outcome before = runPopulation(other, n, jobs, dir + "/reference", 8300 + jobs + 10);
    report("reference", other, n, jobs, before);
    const bool same_ref = readFile(dir + "/reference/population.json") == table;
    same = same && same_ref;
    std::printf("  population.json of this tree and the reference identical: %s\n",
                same_ref ? "yes" : "NO");
    const double ref_share =
        before.figures.count("simulation_share") ? before.figures.at("simulation_share") : 0.0;
    std::printf("RESULT reference_encounters_per_core_hour %.1f\n",
                n * 3600.0 / (before.wall_s * jobs));
    std::printf("RESULT reference_cpu_s_per_encounter %.3f\n", before.cpu_s / n);
    std::printf("RESULT reference_simulation_share %.4f\n", ref_share);
    std::printf("RESULT encounters_per_core_hour_ratio %.3f\n", before.wall_s / now.wall_s);
    std::printf("RESULT cpu_per_encounter_ratio %.3f\n", now.cpu_s / before.cpu_s);
    // A run alone (its worker's stamps in both trees), without the population's fixed costs:
    // what the ratio of encounters per core-hour tends to in a large population.
    if (before.figures.count("worker_wall_sum_s") && now.figures.count("worker_wall_sum_s"))
      std::printf("RESULT worker_wall_ratio %.3f\n",
                  now.figures.at("worker_wall_sum_s") / before.figures.at("worker_wall_sum_s"));
    if (before.figures.count("run_wall_mean_s") && now.figures.count("run_wall_mean_s"))
      std::printf("RESULT run_wall_ratio %.3f\n",
                  now.figures.at("run_wall_mean_s") / before.figures.at("run_wall_mean_s"));
  }
  if (std::getenv("COOPNAV_BENCH_POP_SERIAL")) {
    const Outcome one = runPopulation(self, n, 1, dir + "/serial", 8300 + 2 * jobs + 20);
    const bool same_serial = readFile(dir + "/serial/population.json") == table;
    same = same && same_serial;
    std::printf("  -j 1: %.1f s wall; population.json identical to -j %d: %s\n", one.wall_s, jobs,
                same_serial ? "yes" : "NO");
    std::printf("RESULT population_parallel_speedup %.3f\n", one.wall_s / now.wall_s);
  }
  std::printf("  logs: %s/*.log\n", dir.c_str());
  return same ? 0 : 1;
}
