#include "sweep_command.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <map>
#include <memory>
#include <thread>
#include <tuple>

#include "cli_support.hpp"
#include "local_pool.hpp"
#include "mpi_transport.hpp"
#include "progress.hpp"
#include "step_overrides.hpp"
#include "stop_signals.hpp"
#include "subcommand_parser.hpp"
#include "sweep_report.hpp"

namespace fs = std::filesystem;

namespace mh::cli {
namespace {

struct SweepArgs {
  std::string study, out;
  int jobs = 0;  // 0: every core
  bool report = false;
};

// The sweep's arguments (CLI11, with --help); an exit code when they are
// wrong or help was asked for. Values are checked here with the messages the
// hand-written loop gave.
std::optional<int> parse(const std::vector<std::string>& args, SweepArgs& a,
                         sweep::SweepContext& ctx) {
  const auto app_holder = subcommand_app(
      "sweep",
      "Run every case of STUDY.yaml (docs/sweeps.md) on all cores, or on every rank under "
      "mpirun; one row per case in DIR/results.csv. Started again with the same DIR, it runs "
      "only the cases left.");
  CLI::App& app = *app_holder;
  std::vector<std::string> studies;
  std::string jobs;
  app.add_option("STUDY.yaml", studies, "the study file");
  app.add_option("--out", a.out, "the folder for results.csv, references/ and the report");
  auto* jobs_opt = app.add_option("--jobs", jobs, "local workers, 1 to 4096 (default: every core)");
  const StepOverrideOptions overrides(app, false, false, "of every case");
  app.add_flag("--report", a.report, "write DIR/report.html with the study's plots");
  app.add_flag("--keep-csv", ctx.keep_csv, "keep each case's CSV in DIR/cases/");
  if (const auto code = parse_subcommand(app, args)) return code;

  if (studies.size() > 1) {
    std::cerr << "monohydra: one study file at a time (got '" << studies[0] << "' and '"
              << studies[1] << "')\n";
    return 2;
  }
  if (jobs_opt->count() > 0) {
    const auto n = parse_number("--jobs", jobs);
    if (!n) return 2;
    if (!(*n >= 1 && *n <= 4096) || *n != std::floor(*n)) {  // NaN too
      std::cerr << "monohydra: --jobs expects a whole number from 1 to 4096\n";
      return 2;
    }
    a.jobs = static_cast<int>(*n);
  }
  StepOverrides given;
  if (!overrides.read(given, true)) return 2;
  ctx.dt = given.dt;  // each case's model file gets them (case_run.cpp)
  ctx.t_end = given.t_end;
  if (studies.empty() || a.out.empty()) {
    std::cerr << "monohydra: sweep needs a study file and --out DIR (sweep --help lists its "
                 "options)\n";
    return 2;
  }
  a.study = studies.front();
  return std::nullopt;
}

// The plots must name columns of the table.
std::optional<int> check_plots(const sweep::Study& study) {
  const auto cols = sweep::table_columns(study);
  for (const auto& p : study.plots)
    for (const auto& c : {p.x, p.y})
      if (std::find(cols.begin(), cols.end(), c) == cols.end()) {
        std::string list;
        for (const auto& n : cols) list += (list.empty() ? "" : ", ") + n;
        std::cerr << "monohydra: "
                  << InputError(p.mark, "plots",
                                "no column '" + c + "' in the table (it has " + list + ")")
                         .what()
                  << '\n';
        return 2;
      }
  return std::nullopt;
}

}  // namespace

int run_sweep(const std::vector<std::string>& args) {
  SweepArgs a;
  sweep::SweepContext ctx;
  if (const auto code = parse(args, a, ctx)) return *code;
  try {
    ctx.study = sweep::load_study(a.study);
    ctx.out_dir = a.out;
    sweep::prepare_context(ctx);
  } catch (const InputError& err) {
    std::cerr << "monohydra: " << err.what() << '\n';
    return 2;
  }
  if (const auto code = check_plots(ctx.study)) return *code;
  const volatile std::sig_atomic_t* stop = install_stop_handlers();

  std::unique_ptr<sweep::MpiTransport> mpi;
  if (sweep::launched_by_mpirun()) {
    try {
      mpi = std::make_unique<sweep::MpiTransport>();
    } catch (const std::exception& err) {
      std::cerr << "monohydra: " << err.what() << '\n';
      return 2;
    }
    if (mpi->rank() != 0 && mpi->size() > 1) {
      const int sig = mpi->work(ctx, stop);
      if (sig != 0) mpi->abort(exit_status_for_signal(sig));
      return 0;
    }
  }

  std::unique_ptr<sweep::ResultsTable> table;
  try {
    std::error_code ec;
    fs::create_directories(fs::path(a.out) / "references", ec);
    if (ec) throw std::runtime_error("cannot create '" + a.out + "': " + ec.message());
    table = std::make_unique<sweep::ResultsTable>(a.out, ctx.study, ctx.cases);
  } catch (const std::exception& err) {
    std::cerr << "monohydra: " << err.what() << '\n';
    if (mpi) mpi->abort(2);
    return 2;
  }
  sweep::JobQueue queue(ctx, *table);
  sweep::Progress progress(ctx.cases.size(), ctx.cases.size() - queue.cases_to_run());
  int write_failure = 0;
  const sweep::JobResult on_result = [&](const sweep::Job& job, const std::string& result) {
    if (job.reference) {
      const auto& r = ctx.references[static_cast<std::size_t>(job.index)];
      const std::string what = "reference " + r.name + " of model " +
                               ctx.study.models[static_cast<std::size_t>(r.model)].name;
      progress.note(result.empty()
                        ? what + " ran: " + ctx.reference_csv(r)
                        : what + " did not run (" + result + "): its error metrics stay empty");
      return;
    }
    try {
      table->append(job.index, result);
    } catch (const std::exception& err) {
      if (write_failure == 0) std::cerr << "\nmonohydra: " << err.what() << '\n';
      write_failure = 1;
    }
    progress.case_done(sweep::row_status(result, ctx.study));
  };

  int sig = 0;
  const int workers =
      a.jobs > 0 ? a.jobs : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  if (mpi && mpi->size() > 1) {
    std::cerr << "sweep: " << ctx.cases.size() << " cases on " << mpi->size() - 1
              << " MPI ranks (rank 0 hands them out)\n";
    sig = mpi->coordinate(queue, on_result, stop);
    if (sig != 0) mpi->abort(exit_status_for_signal(sig));
  } else {
    std::cerr << "sweep: " << ctx.cases.size() << " cases on " << workers << " local worker"
              << (workers == 1 ? "" : "s") << '\n';
    sig = sweep::run_local_pool(ctx, queue, workers, on_result, stop);
  }
  if (sig != 0) {
    std::cerr << "\nmonohydra: interrupted by " << signal_name(sig) << ": " << table->rows()
              << " of " << ctx.cases.size() << " cases have their row in '" << table->path()
              << "'; run the same command again to run the others\n";
    return exit_status_for_signal(sig);
  }
  progress.finish();
  if (write_failure != 0) return 1;
  try {
    table->finish();
    std::map<std::string, int> statuses;
    for (const auto& [i, row] : table->row_texts()) ++statuses[sweep::row_status(row, ctx.study)];
    std::cout << "study:   " << ctx.study.name << " (" << a.study << ")\ncases:  ";
    for (const auto& [s, n] : statuses) std::cout << ' ' << n << ' ' << s;
    std::cout << "\nresults: " << table->path() << '\n';
    if (a.report) {
      const auto t = sweep::read_table(table->path());
      std::cout << "report:  " << sweep::write_sweep_report(a.out, ctx.study, t) << '\n';
    }
  } catch (const std::exception& err) {
    std::cerr << "monohydra: " << err.what() << '\n';
    return 1;
  }
  return 0;
}

}  // namespace mh::cli
