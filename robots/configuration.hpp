// VAL configuration words for a PUMA-type arm.
#pragma once

namespace asimov::robots {

struct Configuration {
  bool righty = true;  // RIGHTY / LEFTY
  bool above = true;   // ABOVE / BELOW
  bool noflip = true;  // NOFLIP / FLIP (displayed J5 >= 0)
  bool operator==(const Configuration&) const = default;
};

// Requests pending for the next joint motion to a transformation; unset fields keep the current.
struct ConfigurationRequest {
  int righty = -1, above = -1, noflip = -1;  // -1 unset, 0 false, 1 true
  bool single = true;                        // SINGLE (J6 in (-180,180]) / MULTIPLE
};

}  // namespace asimov::robots
