// Registers freestand's styles with a LIGGGHTS instance built from Debian's
// libliggghts, without rebuilding LIGGGHTS.
//
// Why this file exists: LIGGGHTS fills its style maps at construction from
// compile-time lists (style_fix.h, ...), so a plugin has to add itself to the
// maps afterwards. Force::pair_map is public, but Modify::fix_map and
// Modify::compute_map are private. C++ waives access checks for the
// arguments of an explicit template instantiation ([temp.explicit]/12), so
// the member pointers below can be named legally and stored in a friend
// function. This is the only place that touches LIGGGHTS' private members.

#include "style_registry.h"

#include <dlfcn.h>

#include <algorithm>
#include <map>

#include "force.h"
#include "input.h"
#include "lammps.h"
#include "modify.h"

#include "freestand_style_list.h"  // class definitions of our styles

namespace {

using LAMMPS_NS::Compute;
using LAMMPS_NS::Fix;
using LAMMPS_NS::Input;
using LAMMPS_NS::LAMMPS;
using LAMMPS_NS::Modify;
using LAMMPS_NS::Pair;

// Spelled out: the typedefs FixCreator/ComputeCreator are private too.
using FixMap = std::map<std::string, Fix* (*)(LAMMPS*, int, char**)>;
using ComputeMap = std::map<std::string, Compute* (*)(LAMMPS*, int, int, char**)>;

using CommandMap = std::map<std::string, void (*)(LAMMPS*, int, char**)>;

struct FixMapTag { using type = FixMap* Modify::*; };
struct ComputeMapTag { using type = ComputeMap* Modify::*; };
struct CommandMapTag { using type = CommandMap* Input::*; };

template <typename Tag, typename Tag::type Member>
struct MemberAccess {
  friend typename Tag::type member(Tag) { return Member; }
};
FixMapTag::type member(FixMapTag);
ComputeMapTag::type member(ComputeMapTag);
CommandMapTag::type member(CommandMapTag);
template struct MemberAccess<FixMapTag, &Modify::fix_map>;
template struct MemberAccess<ComputeMapTag, &Modify::compute_map>;
template struct MemberAccess<CommandMapTag, &Input::command_map>;

template <class T> Fix* create_fix(LAMMPS* lmp, int narg, char** arg) {
  return new T(lmp, narg, arg);
}
// LIGGGHTS computes take the index of their first own argument by reference.
template <class T> Compute* create_compute(LAMMPS* lmp, int iarg, int narg, char** arg) {
  return new T(lmp, iarg, narg, arg);
}
template <class T> Pair* create_pair(LAMMPS* lmp) { return new T(lmp); }

// Visits every style of the generated list with the LIGGGHTS style macros.
template <class Visitor> void visit_styles(Visitor&& visit) {
#define FIX_CLASS
#define FixStyle(key, Class) visit("fix", #key, &create_fix<LAMMPS_NS::Class>);
#include "freestand_style_list.h"
#undef FixStyle
#undef FIX_CLASS
#define COMPUTE_CLASS
#define ComputeStyle(key, Class) visit("compute", #key, &create_compute<LAMMPS_NS::Class>);
#include "freestand_style_list.h"
#undef ComputeStyle
#undef COMPUTE_CLASS
#define PAIR_CLASS
#define PairStyle(key, Class) visit("pair", #key, &create_pair<LAMMPS_NS::Class>);
#include "freestand_style_list.h"
#undef PairStyle
#undef PAIR_CLASS
}

struct Registrar {
  LAMMPS* lmp;
  void operator()(const char*, const char* name, Fix* (*f)(LAMMPS*, int, char**)) const {
    (*(lmp->modify->*member(FixMapTag{})))[name] = f;
  }
  void operator()(const char*, const char* name,
                  Compute* (*f)(LAMMPS*, int, int, char**)) const {
    (*(lmp->modify->*member(ComputeMapTag{})))[name] = f;
  }
  void operator()(const char*, const char* name, Pair* (*f)(LAMMPS*)) const {
    (*lmp->force->pair_map)[name] = f;
  }
};

}  // namespace

namespace freestand {

void register_freestand_styles(LAMMPS* lmp) { visit_styles(Registrar{lmp}); }

}  // namespace freestand

// The input command `clear` destroys Modify and Force and builds new ones
// from the compile-time style lists, dropping our styles; it is a built-in
// of Input, so it cannot be replaced through command_map. Both the LAMMPS
// constructor and `clear` finish by calling LAMMPS::post_create() through
// the PLT of libliggghts, so defining it here interposes it (the executable
// exports it, see CMakeLists.txt): the library's own post_create runs, then
// our styles are registered again.
void LAMMPS_NS::LAMMPS::post_create() {
  using PostCreate = void (*)(LAMMPS*);
  static const auto library_post_create =
      reinterpret_cast<PostCreate>(dlsym(RTLD_NEXT, "_ZN9LAMMPS_NS6LAMMPS11post_createEv"));
  library_post_create(this);
  freestand::register_freestand_styles(this);
}

namespace freestand {

std::vector<StyleName> freestand_styles() {
  std::vector<StyleName> names;
  visit_styles([&](const char* kind, const char* name, auto) {
    names.push_back({kind, name});
  });
  return names;
}

}  // namespace freestand

namespace {

template <class Map>
void print_names(std::FILE* out, const char* title, const Map& map, const char* kind) {
  const auto ours = freestand::freestand_styles();
  std::fprintf(out, "\n* %s:\n\n", title);
  int column = 0;
  for (const auto& entry : map) {
    const bool is_ours = std::any_of(ours.begin(), ours.end(), [&](const freestand::StyleName& s) {
      return s.kind == kind && s.name == entry.first;
    });
    const std::string label = entry.first + (is_ours ? " (freestand)" : "");
    std::fprintf(out, "%-32s", label.c_str());
    if (++column % 5 == 0) std::fputc('\n', out);
  }
  std::fputc('\n', out);
}

}  // namespace

namespace freestand {

void print_style_help(LAMMPS* lmp, std::FILE* out) {
  std::fprintf(out,
      "freestand-lmp: LIGGGHTS-PUBLIC 3.8 (Debian libliggghts) with freestand's styles\n\n"
      "Command line options (as for liggghts):\n\n"
      "-echo none/screen/log/both  : echoing of input script (-e)\n"
      "-in filename                : read input from file, not stdin (-i)\n"
      "-help                       : print this help message (-h)\n"
      "-log none/filename          : where to send log output (-l)\n"
      "-nocite                     : disable writing log.cite file (-nc)\n"
      "-partition size1 size2 ...  : assign partition sizes (-p)\n"
      "-plog basename              : basename for partition logs (-pl)\n"
      "-pscreen basename           : basename for partition screens (-ps)\n"
      "-reorder topology-specs     : processor reordering (-r)\n"
      "-screen none/filename       : where to send screen output (-sc)\n"
      "-var varname value          : set index style variable (-v)\n");
  print_names(out, "Command styles", *(lmp->input->*member(CommandMapTag{})), "command");
  print_names(out, "Compute styles", *(lmp->modify->*member(ComputeMapTag{})), "compute");
  print_names(out, "Fix styles", *(lmp->modify->*member(FixMapTag{})), "fix");
  print_names(out, "Pair styles", *lmp->force->pair_map, "pair");
}

}  // namespace freestand
