// uavip bench: the paper's A* and OMPL planners on the legs of benchmark scenarios
// (include/uavip/bench/runner.h).

#include <unistd.h>

#include <filesystem>
#include <iomanip>
#include <iostream>
#include <memory>
#include <sstream>

#include "planners/harness.h"
#include "planners/registry.h"
#include "src/cli/commands.h"
#include "uavip/app/scenario.h"
#include "uavip/bench/report.h"
#include "uavip/bench/runner.h"
#include "uavip/core/error.h"
#include "uavip/io/atomic_file.h"

namespace uavip::cli {
namespace {

namespace fs = std::filesystem;

/// Options of bench, kept alive until dispatch.
struct BenchArgs {
  std::vector<std::string> scenarios;
  std::string planners;
  int runs{5};
  double time_limit_s{1.0};
  double max_total_s{4.0 * 3600.0};
  std::string out{"results.log"};
  bool no_simplify{false};
  std::uint32_t seed{1};
};

std::vector<std::string> splitList(const std::string& text) {
  std::vector<std::string> out;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) {
    const auto b = item.find_first_not_of(" \t");
    const auto e = item.find_last_not_of(" \t");
    if (b == std::string::npos) throw InputError("--planners: empty name in '" + text + "'");
    out.push_back(item.substr(b, e - b + 1));
  }
  return out;
}

std::string hostName() {
  char buf[256] = {0};
  if (::gethostname(buf, sizeof(buf) - 1) != 0) return "UNKNOWN";
  return buf;
}

/// results.log -> results.<ext> (same folder and stem).
std::string sibling(const std::string& log, const std::string& ext) {
  fs::path p(log);
  p.replace_extension(ext);
  return p.string();
}

int benchCommand(const BenchArgs& a, const Verbosity& v) {
  bench::BenchOptions options;
  if (!a.planners.empty()) options.planners = splitList(a.planners);
  options.runs = a.runs;
  options.max_total_s = a.max_total_s;
  options.time_limit_s = a.time_limit_s;
  options.simplify = !a.no_simplify;
  options.seed = a.seed;
  options.validate();
  if (a.out.empty()) throw InputError("-o: give the log file, e.g. results.log");
  // Before any scenario is read: reading one may create (and so seed) a planner.
  if (!planners::seedOmpl(options.seed)) {
    std::cerr << "uavip: warning: OMPL was already seeded; --seed " << options.seed
              << " has no effect\n";
  }
  io::requireDistinctOutputs(
      a.scenarios, {a.out, sibling(a.out, ".csv"), sibling(a.out, ".md"), sibling(a.out, ".png")});
  std::vector<app::Scenario> scenarios;
  for (const auto& path : a.scenarios) scenarios.push_back(app::loadScenario(path));
  const fs::path parent = fs::path(a.out).parent_path();
  if (!parent.empty()) io::ensureDirectory(parent.string());

  const bench::BenchResult r = bench::runBench(scenarios, options, progressPrinter(v));
  std::string name = "uavip_bench";
  for (const auto& s : r.scenarios) name += "_" + s;
  io::StagedOutputs outputs;  // the log, CSV, table and plot are written together
  outputs.write(a.out, bench::benchLog(r, name, hostName()));
  const std::string csv = sibling(a.out, ".csv");
  const std::string md = sibling(a.out, ".md");
  outputs.write(csv, bench::benchCsv(r));
  const std::string markdown = bench::benchMarkdown(r);
  outputs.write(md, markdown);
  const std::string png = sibling(a.out, ".png");
  outputs.write(png, bench::benchPlot(r).png());
  outputs.commit();
  if (!v.quiet) {
    std::cout << markdown;
    std::cout << "\nresults: " << a.out << " (ompl_benchmark_statistics " << a.out
              << " -d results.db), " << csv << ", " << md << ", " << png << "\n";
  }
  return kExitOk;
}

}  // namespace

void addBenchCommands(CLI::App& cli, CommandRegistry& registry) {
  auto a = std::make_shared<BenchArgs>();
  const Verbosity& v = registry.verbosity();
  std::string names;
  for (const auto& n : planners::plannerNames()) names += (names.empty() ? "" : ", ") + n;

  auto* b = cli.add_subcommand(
      "bench",
      "Benchmark the grid A* and OMPL planners on the legs of scenarios; "
      "writes an OMPL benchmark log, a CSV, a Markdown summary and a plot (PNG)");
  b->add_option("scenarios", a->scenarios,
                "Scenario YAML files (legs from their bench: section, or sampled)")
      ->required();
  b->add_option("--planners", a->planners,
                "Comma-separated planners (" + names + "); default: all");
  b->add_option("--runs", a->runs, "Runs per planner and leg")->capture_default_str();
  b->add_option("--time-limit", a->time_limit_s, "Budget per run of an OMPL planner [s]")
      ->capture_default_str();
  b->add_option(
       "--max-total", a->max_total_s,
       "Refuse a bench whose worst case (legs x planners x runs x time limit) exceeds this [s]")
      ->capture_default_str();
  b->add_option("--seed", a->seed, "Seed of OMPL's RNG and of the leg sampling")
      ->capture_default_str();
  b->add_flag("--no-simplify", a->no_simplify, "Keep the planners' raw paths (no PathSimplifier)");
  b->add_option("-o,--out", a->out, "Benchmark log; the .csv, .md and .png go next to it")
      ->capture_default_str();
  registry.add(b, [a, &v] { return benchCommand(*a, v); });
}

}  // namespace uavip::cli
