// Every hard case through its sweep on the MPI backend, in one mpirun (starting MPI once
// costs more than all the renders): rank 0 writes one line per check to RESULTS, and
// the CTest test of each check reads its line (mpi_result.sh).
//
//   mpirun -np N hard_case_mpi RESULTS
#include <cstdio>
#include <exception>
#include <fstream>
#include <string>

#include "hard_run.h"
#include "parallel/cluster.h"
#include "render/distributed.h"

using namespace pvrt;

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: mpirun -np N hard_case_mpi RESULTS\n");
    return 2;
  }
  cluster::Session session;
  const bool root = cluster::rank() == 0;
  auto renderWith = [](const Scene& scene, int w, int h) {
    RenderSettings rs;
    rs.width = w;
    rs.height = h;
    rs.threads = 1;
    rs.schedule.strategy = Strategy::Cyclic;
    return renderDistributed(scene, rs, DistributedSettings{}).render;
  };
  std::ofstream out;
  if (root) out.open(argv[1]);
  for (const std::string& name : hard::caseNames())
    for (const std::string& sweep : hard::sweepsOf(name)) {
      std::string line;
      try {
        line = hard::runCase(name, sweep, "mpi", renderWith, root).line;
      } catch (const std::exception& e) {
        line = "HARD " + name + " " + sweep + " mpi: FAIL " + e.what();
      }
      if (root) {
        out << line << "\n";
        std::printf("%s\n", line.c_str());
      }
    }
  return 0;
}
