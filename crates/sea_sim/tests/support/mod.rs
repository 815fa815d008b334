//! Fixtures shared by the sea_sim integration tests.

/// Overrides that put the tracking scenario's iCub on both feet (the original study's two-feet
/// posture) with a 2 cm, 0.5 Hz CoM sinusoid about the initial CoM.
pub const TWO_FEET: [(&str, &str); 5] = [
    ("robot.contacts", "[\"l_sole\", \"r_sole\"]"),
    ("robot.initial_posture", "two_feet"),
    ("reference.com_origin", "initial"),
    ("reference.com_amplitude", "0.02"),
    ("reference.com_frequency", "0.5"),
];
