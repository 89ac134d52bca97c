// freestand-lmp: the stock `liggghts` binary plus freestand's styles.
//
// Same command line as liggghts (-in, -var, -log, -screen, -echo, ...), runs
// under mpirun. It differs only in registering our styles before the input
// is read, and in answering -h itself so the style list includes them.

#include <mpi.h>

#include <cstdio>
#include <cstring>
#include <exception>
#include <string>
#include <vector>

#include "input.h"
#include "lammps.h"
#include "style_registry.h"

namespace {

bool asks_for_help(int argc, char** argv) {
  for (int i = 1; i < argc; ++i)
    if (!std::strcmp(argv[i], "-h") || !std::strcmp(argv[i], "-help")) return true;
  return false;
}

// Builds an instance that reads no input and prints nothing, to list styles.
int print_help(int argc, char** argv) {
  std::vector<char*> args{argv[0], const_cast<char*>("-screen"), const_cast<char*>("none"),
                          const_cast<char*>("-log"), const_cast<char*>("none")};
  auto* lmp = new LAMMPS_NS::LAMMPS(static_cast<int>(args.size()), args.data(), MPI_COMM_WORLD);
  freestand::register_freestand_styles(lmp);
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  if (rank == 0) freestand::print_style_help(lmp, stdout);
  delete lmp;
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
  if (asks_for_help(argc, argv)) {
    print_help(argc, argv);
  } else {
    auto* lmp = new LAMMPS_NS::LAMMPS(argc, argv, MPI_COMM_WORLD);
    freestand::register_freestand_styles(lmp);
    lmp->input->file();
    delete lmp;
  }
  MPI_Finalize();
  return 0;
}
