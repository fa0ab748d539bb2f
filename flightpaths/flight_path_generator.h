#pragma once
// Deterministic generators for the committed flight paths (flightpaths/README.md),
// one algorithm per header:
//
//   conops.h            conops.csv: the AAR CONOPS approach of thesis 3.1/3.7
//                       (Figures 20-23): 175 m -> contact position, holds near
//                       49, 34 and 32 m
//   conops_variant.h    seeded variants of the approach, for held-out tests
//   boom_schedule.h     conops-boom.csv: conops.csv with the boom operator's
//                       schedule (stowed, lowered, tracking the receptacle)
//   characterization.h  characterization.csv: the 558 ICP characterization
//                       positions of Experiment 1 (Figure 14), 10-110 m, zero
//                       attitude
//   receiver_box.h      the receiver's bounding box (the C-12 of
//                       scenes/c12.glb) and how it projects into the rig
//   holds.h             holds (near-stationary runs) in a path
//   path_summary.h      the summaries aar-make-flightpaths prints
//
// Everything here is a pure function of the rig and the options (a variant's
// seed among them): no clocks, no hidden random state. Ranges are measured from the left camera centre to the
// receiver reference point (docs/frames.md). Positions are in the tanker frame.

#include "boom_schedule.h"
#include "characterization.h"
#include "conops.h"
#include "conops_variant.h"
#include "holds.h"
#include "path_summary.h"
#include "receiver_box.h"
