/* freestand: fix rockslide/hdf5. Writes the channels of a compute rockslide,
   the body poses and the table motion to an HDF5 file; see
   docs/fix_rockslide_hdf5.md. */

#ifdef FIX_CLASS

FixStyle(rockslide/hdf5,FixRockSlideHDF5)

#else

#ifndef LMP_FIX_ROCKSLIDE_HDF5_H
#define LMP_FIX_ROCKSLIDE_HDF5_H

#include <memory>
#include <string>
#include <vector>

#include "fix.h"
#include "freestand/series_file.h"
#include "lmptype.h"

namespace LAMMPS_NS {

class ComputeRockSlide;

class FixRockSlideHDF5 : public Fix {
 public:
  FixRockSlideHDF5(class LAMMPS *lmp, int narg, char **arg);
  ~FixRockSlideHDF5() override;
  int setmask() override;
  void init() override;
  void setup(int) override;
  void end_of_step() override;

 private:
  void open_file();
  class FixRigidConvex *rigid_convex(const std::string &id, const char *keyword);
  void write_sample(const std::vector<double> &collective);

  std::string compute_id_;                        // ID of the compute rockslide
  std::string path_;                              // final file name
  std::string energy_id_;                         // fix whose global vector is the energy ledger, or ""
  std::string contacts_id_;                       // fix rigid/convex whose contact resultants are written, or ""
  std::string scenario_text_;                     // stored as the root attribute "scenario", or ""
  ComputeRockSlide *compute_ = nullptr;           // resolved in init()
  Fix *energy_ = nullptr;                         // resolved in init(), with energy_id_
  class FixRigidConvex *contacts_ = nullptr;      // resolved in init(), with contacts_id_
  std::unique_ptr<freestand::SeriesFile> file_;   // open on rank 0 only
  bigint last_written_ = -1;                      // time step of the last sample
};

}  // namespace LAMMPS_NS

#endif
#endif
