// viewer/src/input/xr_input_mapping.hpp: the controllers as an input source: what the
// OpenXR actions read in a frame (xr/xr_input.hpp) turned into the operator's input.
#pragma once
#include "input/operator_input.hpp"
#include "xr/xr_input.hpp"

namespace viewer {

/// The controllers as an input source: buttons to actions, the thumbsticks to motion (a
/// snap turn, or a smooth one), the pointing hand's aim pose to the pointer's ray (the
/// hand whose designate went down last), both grips held to grab-and-scale.
class XrInputMapping {
  public:
    OperatorInput map(const XrInput& xin, bool snap_turn);

  private:
    int pointer_hand_ = 1;  // right
};

}  // namespace viewer
