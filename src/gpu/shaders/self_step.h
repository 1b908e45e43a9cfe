// The layout shared by self-collision's stages on the device (gpu/device_self_candidates.h,
// gpu/device_self_contacts.h) and their shaders (self_boxes, self_select, self_detect, self_motion,
// self_respond): the phases, the flags, the pairs' words and the push constants, read by C++ and
// by GLSL.
#if defined(__cplusplus)
#pragma once
#include <cstdint>
namespace clothsim::gpu {
using uint = std::uint32_t;
#define CLOTHSIM_SLOT inline constexpr uint
#else
#define CLOTHSIM_SLOT const uint
#endif

// self_boxes.comp's phases, each one pass.
CLOTHSIM_SLOT kBoxesPoints = 0;    // per particle: its motion's box
CLOTHSIM_SLOT kBoxesElements = 1;  // per triangle, then per edge: its particles' boxes' union, grown
CLOTHSIM_SLOT kBoxesGrow = 2;      // per particle: its box grown
CLOTHSIM_SLOT kBoxesCells = 3;     // one invocation: the two grids' cell sizes

struct BoxesPassConstants {
  uint phase;  // kBoxes*
  uint particles;
  uint triangles;
  uint edges;
};

// A candidate pair as the stages after the search keep it, two words: the first element with
// kEdgePairBit set for two edges (clear for a particle and a triangle), and the second element.
CLOTHSIM_SLOT kEdgePairBit = 0x80000000u;

// self_select.comp's phases: which of the search's pairs are kept (all, or those nearer than the
// reach at the positions given), then the kept ones written in order.
CLOTHSIM_SLOT kSelectMeasure = 0;
CLOTHSIM_SLOT kSelectWrite = 1;

struct SelectPassConstants {
  uint phase;        // kSelect*
  uint point_pairs;  // the search's particle-triangle pairs, then
  uint edge_pairs;   // its edge pairs
  uint keep_all;     // 1: every pair kept (no positions to measure at)
};

// self_detect.comp's flags of a candidate.
CLOTHSIM_SLOT kPairActive = 1;    // the elements' boxes over the motion, grown by half the thickness, overlap
CLOTHSIM_SLOT kPairNear = 2;      // within the thickness at the start or the end, apart at the start
CLOTHSIM_SLOT kPairTouching = 4;  // its first touch is within the motion

struct DetectPassConstants {
  uint candidates;
};

// self_list.comp's phases: the candidates with any bit of a mask, counted, then listed, then (one
// invocation) how many.
CLOTHSIM_SLOT kListCount = 0;
CLOTHSIM_SLOT kListWrite = 1;
CLOTHSIM_SLOT kListTotal = 2;

struct ListPassConstants {
  uint phase;  // kList*
  uint candidates;
  uint mask;  // kPair* bits
  uint unused;
};

// self_motion.comp's phases: per workgroup of particles the largest squared motions, then their
// largest over the workgroups (a maximum: the same in any order).
CLOTHSIM_SLOT kMotionBlocks = 0;
CLOTHSIM_SLOT kMotionTotal = 1;
CLOTHSIM_SLOT kMotionWorkgroup = 256;
// The maxima, each a squared distance: how far a particle is from where the candidates were found,
// at the motion's start or end; and how far it moves over the motion.
CLOTHSIM_SLOT kMotionFromFound = 0;
CLOTHSIM_SLOT kMotionOfStep = 1;
CLOTHSIM_SLOT kMotionValues = 2;

struct MotionPassConstants {
  uint phase;  // kMotion*
  uint particles;
  uint blocks;  // workgroups of kMotionBlocks
  uint unused;
};

// self_respond.comp's phases, over a list of flagged candidates (the near ones, or the touching):
CLOTHSIM_SLOT kRespondCount = 0;       // per pair: its particles' counts of pairs
CLOTHSIM_SLOT kRespondFill = 1;        // per pair: its 4 entries in its particles' segments of the table
CLOTHSIM_SLOT kRespondSort = 2;        // per particle: its segment sorted in pair order
CLOTHSIM_SLOT kRespondShare = 3;       // per pair: its share, 1 / the most pairs any of its free particles is in
CLOTHSIM_SLOT kRespondNearStart = 4;   // per near pair: its geometry at the step's start
CLOTHSIM_SLOT kRespondProximity = 5;   // per near pair: its push and its velocities' change
CLOTHSIM_SLOT kRespondImpact = 6;      // per touching pair: its closing motion removed
CLOTHSIM_SLOT kRespondGather = 7;      // per particle: its pairs' changes, in pair order

// Counters the responses add to (integers: the same in any order).
CLOTHSIM_SLOT kCounterPushed = 0;   // near pairs pushed in the first round
CLOTHSIM_SLOT kCounterImpacts = 1;  // responses to touching pairs
CLOTHSIM_SLOT kCounters = 2;

// Reals per listed pair: its geometry (the normal, 4 weights and distance: at the start for a near
// pair, at its last touch for a touching one) and 1 once it has responded in the stage (its
// velocities then go on being made inelastic after its positions are set); and the change a round
// asks for (the position change and the velocity change along which the particles move in
// proportion to c_k w_k, the effective inverse mass K, the pair's share).
CLOTHSIM_SLOT kGeometryReals = 9;
CLOTHSIM_SLOT kChangeReals = 8;

// The mark the gather leaves in a ledger of moved particles (the obstacle pass's `moved`, where
// obstacle_contacts.comp marks 1) on a particle it is the first to change, its state before the
// change kept beside it, so that the two passes' energy change is booked together
// (obstacle_energy_elements.comp).
CLOTHSIM_SLOT kMovedBySelf = 2;

struct RespondPassConstants {
  uint phase;  // kRespond*
  uint pairs;  // listed
  uint particles;
  uint first_round;  // 1: count the pushed pairs
  uint ledger;       // 1: the gather keeps the ledger of moved particles
};

#if defined(__cplusplus)
#undef CLOTHSIM_SLOT
}  // namespace clothsim::gpu
#endif
