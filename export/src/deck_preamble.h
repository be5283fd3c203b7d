#ifndef BOUNCECAL_EXPORT_SRC_DECK_PREAMBLE_H_
#define BOUNCECAL_EXPORT_SRC_DECK_PREAMBLE_H_

#include <fmt/core.h>

#include <string>

// The opening commands of every deck, after its comment header: written once here so that the
// drop and packing decks of one engine cannot drift apart.
namespace bouncecal::calibrate::deck_text {

// LAMMPS (GRANULAR package): SI units; spheres that carry diameter and density; a box with fixed
// walls (z periodic in 2D, where LAMMPS requires it); newton off and ghost velocities, which the
// granular pair styles and wall/gran need for their contact history and dashpot. `atom_map`:
// the deck reads one atom by id (z[1] in a variable), which needs an atom map.
inline std::string LammpsPreamble(int dimension, bool atom_map) {
  return fmt::format(
      "units           si\n"
      "atom_style      sphere\n"
      "{}"
      "dimension       {}\n"
      "boundary        {}\n"
      "newton          off\n"
      "comm_modify     vel yes\n",
      atom_map ? "atom_modify     map array\n" : "", dimension, dimension == 2 ? "f f p" : "f f f");
}

// LIGGGHTS-PUBLIC 3.x: the same set-up in its dialect (atom_style granular, communicate), in the
// order its examples use; always with the atom map.
inline std::string LiggghtsPreamble() {
  return "atom_style      granular\n"
         "atom_modify     map array\n"
         "boundary        f f f\n"
         "newton          off\n"
         "communicate     single vel yes\n"
         "units           si\n";
}

}  // namespace bouncecal::calibrate::deck_text

#endif  // BOUNCECAL_EXPORT_SRC_DECK_PREAMBLE_H_
