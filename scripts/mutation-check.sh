#!/usr/bin/env bash
# Mutation check (issue 11): does the test suite fail when the code it tests is broken?
#
# Each mutation below is a small, deliberate bug in the force, integrator, event or collision
# code: a dropped mass, a flipped sign, a skipped stage, an off-by-one. For each one the script
# changes one line of a scratch clone of HEAD, rebuilds it (incrementally) and runs the tests
# named for it; a mutation is caught when at least one of them fails. Every mutation must be
# caught; the script exits 1 otherwise, and prints a table for docs/testing.md.
#
#   scripts/mutation-check.sh [SCRATCH_DIR]      (default: a new temporary folder)
#
# It checks the committed HEAD, not the working tree. It needs what the README's test command
# needs (the Debian packages of scripts/install-deps.sh). A mutation that does not apply (its line
# changed) or does not build is reported as such and counts as a failure of the check: the list
# must follow the code.
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
scratch="${1:-$(mktemp -d)}"
copy="$scratch/clothsim"

# file @ the exact text of one line (found once) @ what it becomes @ ctest -R regex @ description
mutations=(
  "src/forces/forces.cpp@Vec3 sum = model.particle_mass[p] * gravity - drag * velocity[p];@Vec3 sum = gravity - drag * velocity[p];@Forces|LatticeKernel|ConnectorElement|RadialElement|Kernels|SingleSpring|Conservation@gravity without the mass (general path)"
  "src/forces/lattice_kernel.cpp@Vec3 f = mass[p] * k.gravity - k.drag * v;@Vec3 f = k.gravity - k.drag * v;@Forces|LatticeKernel|ConnectorElement|RadialElement|Kernels|SingleSpring|Conservation@gravity without the mass (lattice kernel)"
  "src/forces/element.h@const double tension = stiffness * (length - rest_length) + damping * extension_rate;@const double tension = stiffness * (length - rest_length) - damping * extension_rate;@Forces|LatticeKernel|ConnectorElement|RadialElement|Kernels|SingleSpring|Conservation@connector damping with the wrong sign"
  "src/forces/element.h@Vec3 gradient_b() const { return -(1.0 / length_b) * direction_b; }@Vec3 gradient_b() const { return (1.0 / length_b) * direction_b; }@Forces|LatticeKernel|ConnectorElement|RadialElement|Kernels|SingleSpring|Conservation@radial spring gradient with the wrong sign on one arm"
  "src/integrators/tableau.h@{1.0 / 6.0, 1.0 / 3.0, 1.0 / 3.0, 1.0 / 6.0},@{1.0 / 6.0, 1.0 / 3.0, 1.0 / 6.0, 1.0 / 3.0},@Integrators|AdaptiveRungeKutta|Convergence|Tableau|Conservation|PaperScenes@RK4 weights of the last two stages swapped"
  "src/integrators/explicit_runge_kutta.cpp@    for (int l = 0; l < i; ++l) {@    for (int l = 0; l + 1 < i; ++l) {@Integrators|AdaptiveRungeKutta|Convergence|Tableau|Conservation|PaperScenes@Runge-Kutta stage sums (the Nystrom position rows) one term short (off by one)"
  "src/integrators/symplectic_euler.cpp@state.position[p] += h * state.velocity[p];@state.position[p] += 0.5 * h * state.velocity[p];@Integrators|AdaptiveRungeKutta|Convergence|Tableau|Conservation|PaperScenes@symplectic Euler moves half the step"
  "src/integrators/block_system.cpp@const Mat3 a = stiffness_scale * jacobian.stiffness + damping_scale * jacobian.damping;@const Mat3 a = damping_scale * jacobian.damping;@ImplicitEuler@implicit Euler's matrix without the connectors' stiffness"
  "src/integrators/stencil_matrix.h@      lower += transposed_times(block_[(node - d) * slots_ + s], x[node - d]);@      lower += times(block_[(node - d) * slots_ + s], x[node - d]);@SymmetricStencilMatrix|LatticeMultigrid@the V-cycle's stored matrix not transposed below the diagonal (interior rows)"
  "src/integrators/dynamics.cpp@position[anchor.particle] = anchor.path.position(time);@(void)anchor;@AnchorPath|KeyframedAnchors|RuntimeAnchors|Conservation|PaperScenes@anchored particles not put on their path"
  "src/events/spring_events.cpp@  break_connector(model, connector, state.time);@  (void)connector;@Tearing|ChangingScenes|EventRuns@a connector past its limit not broken"
  "src/events/spring_events.cpp@      set_connector_rest_length(model, connector, new_rest);@      (void)new_rest;@PermanentStretching|ChangingScenes|EventRuns@a yielded connector keeps its rest length"
  "src/collision/obstacle_contacts.cpp@Vec3 position = contact_point + std::max(0.0, thickness - contact.distance) * n;@Vec3 position = contact_point;@ObstacleContacts@obstacle contacts not pushed out to the thickness"
  "src/collision/self_contacts.cpp@if (!resolve_impacts(model, state, start, counts, threads)) move_zones(model, state, start, counts, threads);@(void)counts;@SelfContacts|SelfCollision.CornersBroughtTogetherNeverCross@self-collision without its impact stages"
  "src/integrators/explicit_runge_kutta.cpp@  step_control::transfer_controller(archive, \"rkf45\", controller_);@  (void)archive;@SimulationCheckpoint|KilledRunTest@a checkpoint without RKF45's next step"
  "src/integrators/implicit_euler.cpp@  archive.array(\"implicit_euler.dv\", system_.solution);@  (void)archive;@SimulationCheckpoint|KilledRunTest@a checkpoint without implicit Euler's warm start"
  "src/integrators/imex.cpp@  step_control::transfer_controller(archive, \"imex\", controller_);@  (void)archive;@SimulationCheckpoint|KilledRunTest@a checkpoint without imex's next step"
  "src/integrators/imex.cpp@    trial_damping_work_ += weight[j] * stage_rate_[j].damping_power;@    trial_damping_work_ += (j == 0 ? h : 0.0) * stage_rate_[j].damping_power;@ImexPaperScene|ImexEvents@imex's damping work booked from the first stage only"
  "src/run/run_recorder.cpp@  if (impl.model->revision != model.revision) impl.model = std::make_shared<const ClothModel>(model);@  (void)model;@FrameModel@the pictures drawn with the model the run started from"
  "src/scene/scene_memory.cpp@  if (allowance.checked) return;@  return;@SceneMemory@make_simulation without the memory check"
  "src/sim/step_diagnosis.cpp@    if (std::abs(rest_angle - end) < kKinkWindow) continue;@    (void)rest_angle;@StepDiagnosis@a radial spring at rest on the kink taken for at it"
  "src/events/spring_events.cpp@      if (spring_laws::connector_breaks(length, model.connector_original_length[e], model.connector_break_strain[e])) {@      if (spring_laws::connector_breaks(length, model.connector_rest_length[e], model.connector_break_strain[e])) {@EventStageLaws@the break strain measured from the rest length a yield left"
  "src/integrators/symplectic_euler.cpp@  count_evaluations(dynamics_.evaluations());@  stats_.force_evaluations = dynamics_.evaluations();@KilledRunTest@a resumed run's force evaluations counted from the checkpoint on"
  "src/forces/element_math.inc@    result.force_on_b -= (energy * fade_c.value * fade_b.slope) * g.unit_b;@    (void)energy;@RadialFade|RadialElement|RadialJacobian|LatticeKernel@the faded radial spring without the product rule's pull along arm b"
  "src/forces/lattice_kernel.cpp@    fade[p] = exists ? f.value : Real(1);@    fade[p] = Real(1);@LatticeKernel|Float32Forces@the lattice kernel's radial springs not faded as an arm vanishes"
  "src/events/spring_events.cpp@      state.plastic_work += element::radial_energy(x[centre], x[b], x[c], new_rest, stiffness, fade[0], fade[1]) -@      state.plastic_work += element::radial_energy(x[centre], x[b], x[c], new_rest, stiffness, 0.0, 0.0) -@EventStageLaws@a crease's plastic work booked from the unfaded energy"
  "src/forces/lattice_kernel.cpp@  for (std::size_t p = begin >= cols ? begin - cols : 0; p < end; ++p) fading |= south[p] < Real(1) ? 1 : 0;@  for (std::size_t p = begin >= cols ? begin : 0; p < end; ++p) fading |= south[p] < Real(1) ? 1 : 0;@LatticeKernel@a band's fade check without the north arms of its first row"
)

echo "scratch clone: $copy"
rm -rf "$copy"
git clone --quiet "$root" "$copy"
cmake -S "$copy" -B "$copy/build" -G Ninja -DCMAKE_BUILD_TYPE=Release > "$scratch/configure.log"
echo "building the unchanged clone (once)..."
cmake --build "$copy/build" > "$scratch/build.log" 2>&1
# The tests named for each mutation must pass before it is applied.
echo "| # | mutation | file | tests run | result |"
echo "|---|---|---|---|---|"
missed=0
number=0
for entry in "${mutations[@]}"; do
  IFS='@' read -r file original mutated tests description <<< "$entry"
  number=$((number + 1))
  shown="${tests//|/\\|}"  # the regex in a Markdown table cell
  target="$copy/$file"
  count=$(grep -cF -- "$original" "$target" || true)
  if [[ "$count" != 1 ]]; then
    echo "| $number | $description | \`$file\` | \`$shown\` | NOT APPLIED: the line occurs $count times |"
    missed=$((missed + 1))
    continue
  fi
  cp "$target" "$scratch/original"
  ORIGINAL="$original" MUTATED="$mutated" perl -0pi -e 's/\Q$ENV{ORIGINAL}\E/$ENV{MUTATED}/' "$target"
  if ! cmake --build "$copy/build" > "$scratch/mutation-$number.build.log" 2>&1; then
    result="NOT BUILT (see $scratch/mutation-$number.build.log)"
    missed=$((missed + 1))
  elif (cd "$copy/build" && ctest -j2 -R "$tests" > "$scratch/mutation-$number.test.log" 2>&1); then
    result="**MISSED**: every test passed"
    missed=$((missed + 1))
  else
    failed=$(grep -cE '^\s+[0-9]+ - ' "$scratch/mutation-$number.test.log" || true)
    first=$(grep -m1 -oE '^\s+[0-9]+ - [^ ]+' "$scratch/mutation-$number.test.log" | sed -E 's/^\s+[0-9]+ - //')
    result="caught: $failed failed, e.g. \`$first\`"
  fi
  echo "| $number | $description | \`$file\` | \`$shown\` | $result |"
  cp "$scratch/original" "$target"
done
cmake --build "$copy/build" > /dev/null 2>&1 || true
if [[ "$missed" != 0 ]]; then
  echo "$missed of $number mutations were not caught" >&2
  exit 1
fi
echo "all $number mutations were caught"
