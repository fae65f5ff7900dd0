/* -*- c++ -*- ----------------------------------------------------------
   Helpers for in-process LAMMPS GoogleTest files (unittest/lammps/test_*.cpp).

   Every test_*.cpp in unittest/lammps/ is built as its own executable that
   links hardsphere + liblammps + MPI + GTest::gtest (NOT gtest_main).
   Including this header provides main() (MPI_Init, RUN_ALL_TESTS,
   MPI_Finalize). Exactly one translation unit per executable may define
   main(): a TU that includes this header but must not define main()
   defines HS_TEST_NO_MAIN before the #include.

   The build's paths (build/lmp, the repository root, the plugin) are in
   hs_test_paths.h (hs_test_paths::lmp_binary, source_dir, plugin_path, ...).
   Tests run with their working directory in a per-executable scratch dir
   (build/unittest/work/<target>), so output files may be written to ".".

   IMPORTANT (Debian's liblammps is built WITHOUT LAMMPS_EXCEPTIONS): any
   LAMMPS error (Error::all/one) inside HSLammps::cmd()/file() prints the
   message and terminates the whole test process (exit(1) or MPI_Abort);
   with LAMMPS 2025 it throws a LAMMPSException out of the test instead.
   Test expected errors through run_lmp() (a separate lmp process) instead.
   Since HSLammps uses "-screen none", such an error is silent: run the test
   with HS_TEST_VERBOSE=1 to see LAMMPS' screen output and the message.
------------------------------------------------------------------------- */

#ifndef HS_TEST_MAIN_H
#define HS_TEST_MAIN_H

#include "hardsphere_registry.h"
#include "hs_test_paths.h"

#include "input.h"
#include "lammps.h"
#include "library.h"
#include "modify.h"

#include "gtest/gtest.h"

#include <mpi.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

extern char **environ;

// An in-process LAMMPS instance with the HARDSPHERE styles registered.
class HSLammps {
 public:
  LAMMPS_NS::LAMMPS *lmp = nullptr;

  explicit HSLammps(const std::vector<std::string> &extra_args = {})
  {
    std::vector<std::string> args = {"hstest", "-log",  "none", "-screen",
                                     "none",   "-echo", "none", "-nocite"};
    // HS_TEST_VERBOSE=1 in the environment: keep LAMMPS screen output (with
    // "-screen none" an ERROR message is printed nowhere before exit(1))
    const char *verbose = getenv("HS_TEST_VERBOSE");
    if (verbose && *verbose && std::string(verbose) != "0") args = {"hstest", "-log", "none", "-nocite"};
    args.insert(args.end(), extra_args.begin(), extra_args.end());
    std::vector<char *> argv;
    for (auto &a : args) argv.push_back(const_cast<char *>(a.c_str()));
    argv.push_back(nullptr);
    lmp = new LAMMPS_NS::LAMMPS((int) args.size(), argv.data(), MPI_COMM_WORLD);
    hardsphere_register_styles(lmp);
  }
  ~HSLammps() { delete lmp; }
  HSLammps(const HSLammps &) = delete;
  HSLammps &operator=(const HSLammps &) = delete;

  // execute one input line (Input::one)
  // NOTE: "clear" drops the HARDSPHERE styles; call register_styles() after it.
  void cmd(const std::string &line) { lmp->input->one(line); }
  void cmds(const std::vector<std::string> &lines)
  {
    for (const auto &l : lines) cmd(l);
  }
  void file(const std::string &path) { lmp->input->file(path.c_str()); }
  void register_styles() { hardsphere_register_styles(lmp); }
  // current value of a thermo keyword (valid after a run/setup)
  double thermo(const char *keyword) { return lammps_get_thermo(lmp, keyword); }
  // a multi-line input text, one command per non-empty line
  void lines(const std::string &text)
  {
    size_t start = 0;
    while (start <= text.size()) {
      size_t end = text.find('\n', start);
      if (end == std::string::npos) end = text.size();
      if (end > start) cmd(text.substr(start, end - start));
      start = end + 1;
    }
  }
  // value of an equal-style variable (NaN if it does not evaluate)
  double variable(const char *name)
  {
    auto *p = (double *) lammps_extract_variable(lmp, name, nullptr);
    if (!p) return NAN;
    const double val = *p;
    lammps_free(p);
    return val;
  }
  // element k (0-based) of fix ID's global vector
  double fix_vector(const char *id, int k)
  {
    auto *p = (double *) lammps_extract_fix(lmp, id, 0, 1, k, 0);
    if (!p) return -1.0;
    const double val = *p;
    lammps_free(p);
    return val;
  }
};

// mean of block means and its standard error (the blocks taken as
// independent): the error bar of the statistical checks
inline void mean_se(const std::vector<double> &x, double &mean, double &se)
{
  const double n = x.size();
  mean = 0.0;
  for (double v : x) mean += v;
  mean /= n;
  double s2 = 0.0;
  for (double v : x) s2 += (v - mean) * (v - mean);
  se = std::sqrt(s2 / (n - 1.0) / n);
}

// A scratch file name private to this process: ctest -j runs the cases of
// one test executable as parallel processes in the same directory, so a
// fixed name would let two of them overwrite each other's output.
inline std::string scratch_name(const std::string &base)
{
  return base + "." + std::to_string((long) getpid());
}

struct RunResult {
  int exit_code;         // exit status of lmp / mpirun (-1: not exited normally)
  std::string output;    // stdout + stderr
};

namespace hs_test_detail {
inline std::string shell_quote(const std::string &s)
{
  std::string q = "'";
  for (char c : s) {
    if (c == '\'')
      q += "'\\''";
    else
      q += c;
  }
  return q + "'";
}

// environment for the child: drop the variables the (singleton) MPI runtime
// of this test process exported, otherwise the child lmp/mpirun would try
// to join our MPI job.
inline std::vector<std::string> child_environment(bool mpirun)
{
  std::vector<std::string> env;
  static const char *drop[] = {"OMPI_", "PMIX_", "ORTE_", "OPAL_", "PMI_", "HYDRA_"};
  for (char **e = environ; e && *e; ++e) {
    std::string kv(*e);
    bool keep = true;
    for (const char *p : drop)
      if (kv.compare(0, strlen(p), p) == 0) keep = false;
    if (keep) env.push_back(kv);
  }
  if (mpirun) {
    env.emplace_back("OMPI_ALLOW_RUN_AS_ROOT=1");
    env.emplace_back("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1");
    env.emplace_back("OMPI_MCA_rmaps_base_oversubscribe=1");
  }
  return env;
}
}    // namespace hs_test_detail

// Run a LAMMPS executable (binary) on input_text (written to a temporary
// file in the current directory) with "-in file -log none -echo screen"
// plus extra_args; nprocs > 1 runs under "mpirun -np N --oversubscribe".
inline RunResult run_program(const std::string &binary, const std::string &input_text,
                             const std::vector<std::string> &extra_args = {}, int nprocs = 1)
{
  using namespace hs_test_detail;
  char tmpl[] = "hs_input_XXXXXX";
  int fd = mkstemp(tmpl);
  if (fd < 0) return {-1, std::string("mkstemp failed: ") + strerror(errno)};
  FILE *fp = fdopen(fd, "w");
  fputs(input_text.c_str(), fp);
  fclose(fp);
  const std::string infile(tmpl);

  std::string cmd;
  if (nprocs > 1) cmd = "mpirun -np " + std::to_string(nprocs) + " --oversubscribe ";
  cmd += shell_quote(binary) + " -in " + shell_quote(infile) + " -log none -echo screen";
  for (const auto &a : extra_args) cmd += " " + shell_quote(a);
  cmd += " 2>&1";

  std::vector<std::string> envs = child_environment(nprocs > 1);
  std::vector<char *> envp;
  for (auto &e : envs) envp.push_back(const_cast<char *>(e.c_str()));
  envp.push_back(nullptr);

  int pipefd[2];
  if (pipe(pipefd) != 0) {
    unlink(infile.c_str());
    return {-1, "pipe failed"};
  }
  fflush(nullptr);
  pid_t pid = fork();
  if (pid == 0) {
    close(pipefd[0]);
    dup2(pipefd[1], STDOUT_FILENO);
    dup2(pipefd[1], STDERR_FILENO);
    close(pipefd[1]);
    int devnull = open("/dev/null", O_RDONLY);
    if (devnull >= 0) dup2(devnull, STDIN_FILENO);
    execle("/bin/sh", "sh", "-c", cmd.c_str(), (char *) nullptr, envp.data());
    _exit(127);
  }
  close(pipefd[1]);
  RunResult res{-1, ""};
  if (pid < 0) {
    close(pipefd[0]);
    unlink(infile.c_str());
    res.output = "fork failed";
    return res;
  }
  char buf[4096];
  ssize_t n;
  while ((n = read(pipefd[0], buf, sizeof(buf))) != 0) {
    if (n < 0) {
      if (errno == EINTR) continue;
      break;
    }
    res.output.append(buf, (size_t) n);
  }
  close(pipefd[0]);
  int status = 0;
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {}
  if (WIFEXITED(status)) res.exit_code = WEXITSTATUS(status);
  unlink(infile.c_str());
  return res;
}

// the same with our lmp driver (build/lmp)
inline RunResult run_lmp(const std::string &input_text,
                         const std::vector<std::string> &extra_args = {}, int nprocs = 1)
{
  return run_program(hs_test_paths::lmp_binary, input_text, extra_args, nprocs);
}

// the run ends without error (exit code 0) and its output holds every
// string of `present` and none of `absent` (hs_errors::expect_error() is
// the failing counterpart); returned for the checks of its printed values
inline RunResult expect_runs(const std::string &input_text,
                             const std::vector<std::string> &present = {},
                             const std::vector<std::string> &absent = {},
                             const std::vector<std::string> &extra_args = {}, int nprocs = 1)
{
  RunResult r = run_lmp(input_text, extra_args, nprocs);
  EXPECT_EQ(r.exit_code, 0) << r.output;
  for (const auto &s : present)
    EXPECT_NE(r.output.find(s), std::string::npos) << "missing '" << s << "' in:\n" << r.output;
  for (const auto &s : absent)
    EXPECT_EQ(r.output.find(s), std::string::npos) << "unexpected '" << s << "' in:\n" << r.output;
  return r;
}

#ifndef HS_TEST_NO_MAIN
int main(int argc, char **argv)
{
  MPI_Init(&argc, &argv);
  ::testing::InitGoogleTest(&argc, argv);
  int rc = RUN_ALL_TESTS();
  MPI_Finalize();
  return rc;
}
#endif

#endif
