// gather_forces's sum (src/forces/forces.cpp), shared by gather_forces.comp and
// stage_acceleration.comp: gravity and air drag on particle p, then its element slots in the gather
// table's order (model/gather_table.h): the CPU's operations in the CPU's order, no atomics. The
// includer declares the buffers particle_mass, environment, gather_offset, gather_slot and
// slot_force.
#include "gpu/shaders/environment_force.glsl"

Vec3 gathered_force(uint p, Vec3 v) {
  Vec3 sum = environment_force(p, v);
  for (uint k = gather_offset[p]; k < gather_offset[p + 1]; ++k) {
    const uint slot = gather_slot[k];
    sum += Vec3(slot_force[3 * slot], slot_force[3 * slot + 1], slot_force[3 * slot + 2]);
  }
  return sum;
}
