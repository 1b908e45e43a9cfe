// A particle's place in a rows x cols lattice (build_lattice's numbering, p = row cols + col):
// whether it has a neighbour in each direction (0 east, 1 south, 2 west, 3 north) and which.
// The lattice path's passes (lattice_elements, lattice_events_*) walk a particle's springs by it.
#ifndef CLOTHSIM_LATTICE_CELL_GLSL
#define CLOTHSIM_LATTICE_CELL_GLSL
struct LatticeCell {
  bool has[4];
  uint neighbour[4];
};

LatticeCell lattice_cell(uint p, uint rows, uint cols) {
  const uint row = p / cols;
  const uint col = p % cols;
  LatticeCell cell;
  cell.has = bool[4](col + 1u < cols, row + 1u < rows, col > 0u, row > 0u);
  cell.neighbour = uint[4](p + 1u, p + cols, p - 1u, p - cols);
  return cell;
}

// Where the connector of arm d of particle p keeps its values in `event_params` (east and south
// its own, west and north its neighbour's): its original length sets the fade of the radial
// springs on the arm (element_math.inc, kRadialFadeFraction).
uint arm_event_params(uint d, LatticeCell cell, uint p) {
  if (d < 2u) return p * kEventParams + kEventsPerConnector * d;
  return cell.neighbour[d] * kEventParams + kEventsPerConnector * (d - 2u);
}

// The arms of a particle's radial springs, kRadialArmB and kRadialArmC, in build_lattice's order:
// the model's table.
#include "model/lattice_springs.inc"

#endif
