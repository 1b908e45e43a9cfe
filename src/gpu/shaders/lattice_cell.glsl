// A particle's place in a rows x cols lattice (build_lattice's numbering, p = row cols + col):
// whether it has a neighbour in each direction (0 east, 1 south, 2 west, 3 north) and which.
// The lattice path's passes (lattice_elements, lattice_events_*) walk a particle's springs by it.
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

// The arms of a particle's radial springs, kRadialArmB and kRadialArmC, in build_lattice's order:
// the model's table.
#include "model/lattice_springs.inc"
