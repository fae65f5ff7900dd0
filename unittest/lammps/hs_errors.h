/* -*- c++ -*- ----------------------------------------------------------
   Shared helpers of the tests of invalid set-ups. LAMMPS here is built
   without exceptions (an error exits the process), so every case runs in
   its own lmp process through run_lmp(). Include after hs_test_main.h.
------------------------------------------------------------------------- */

#ifndef HS_ERRORS_H
#define HS_ERRORS_H

#include "hs_test_main.h"

#include <string>
#include <vector>

namespace hs_errors {

// the run fails with an ERROR whose output contains every needle
inline void expect_error(const std::string &input, const std::vector<std::string> &needles)
{
  RunResult r = run_lmp(input);
  EXPECT_NE(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("ERROR"), std::string::npos) << r.output;
  for (const auto &n : needles)
    EXPECT_NE(r.output.find(n), std::string::npos) << "missing '" << n << "' in:\n" << r.output;
}

// two atoms of type 1 at (x1,0,0) and (x2,0,0) in a box [-5,5]^3; 'extra'
// (commands) and 'fix' are spliced in before a run of 10 steps
inline std::string two_atoms(const std::string &x1, const std::string &x2, const std::string &fix,
                             const std::string &extra = "", const std::string &boundary = "f f f",
                             const std::string &style = "atomic")
{
  return "units lj\natom_style " + style + "\natom_modify map array\nboundary " + boundary +
      "\nregion box block -5 5 -5 5 -5 5 units box\ncreate_box 1 box\n"
      "create_atoms 1 single " + x1 + " 0 0 units box\n"
      "create_atoms 1 single " + x2 + " 0 0 units box\n"
      "mass 1 1.0\ncomm_modify cutoff 3.0\n" + extra + fix + "\nrun 10\n";
}

}    // namespace hs_errors

#endif
