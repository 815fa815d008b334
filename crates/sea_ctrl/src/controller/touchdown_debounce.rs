//! A foot's loaded state from its force/torque sensor's readings, debounced
//! (`walking.touchdown_debounce`, [`DebouncedLoad`]): the walking controller's touchdowns
//! (`contact_phase.rs`) read this state, not each reading, so that a landing's force
//! chattering about the touchdown threshold at a fast whole-body loop (1 kHz) does not toggle
//! the foot's task every period (docs/findings/walking.md, "Touchdowns at a 1 kHz whole-body
//! loop").

/// A foot's loaded state from its sensor's readings, debounced (`walking.touchdown_debounce`):
/// it changes once the readings have disagreed with it for the debounce time, each reading
/// standing for the period before it, so a debounce of at most one period lets every reading
/// count at once.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct DebouncedLoad {
    /// The state the controller acts on (`false` before any reading).
    pub loaded: bool,
    /// The time of the first reading that disagreed with `loaded` since it last agreed [s]
    /// (`None`: the last reading agreed).
    disagreeing_since: Option<f64>,
}

impl DebouncedLoad {
    /// Takes the reading at `t` [s] (`reading_loaded`: its normal force above the touchdown
    /// force), `period` [s] after the last one, with the debounce time `debounce` [s];
    /// returns the state.
    pub fn update(&mut self, reading_loaded: bool, t: f64, period: f64, debounce: f64) -> bool {
        if reading_loaded == self.loaded {
            self.disagreeing_since = None;
            return self.loaded;
        }
        let since = *self.disagreeing_since.get_or_insert(t);
        if t - since + period >= debounce - 1e-9 {
            self.loaded = reading_loaded;
            self.disagreeing_since = None;
        }
        self.loaded
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The readings of `forces` every `period` from `period` on, through a debounce of
    /// `debounce`: the states taken.
    fn debounced(forces: &[bool], period: f64, debounce: f64) -> Vec<bool> {
        let mut load = DebouncedLoad::default();
        (0..forces.len())
            .map(|k| load.update(forces[k], (k + 1) as f64 * period, period, debounce))
            .collect()
    }

    #[test]
    fn a_debounce_of_one_period_lets_every_reading_count_at_once() {
        let readings = [true, false, true, true, false, false];
        assert_eq!(debounced(&readings, 0.01, 0.01), readings);
        assert_eq!(debounced(&readings, 0.001, 0.0), readings);
    }

    #[test]
    fn a_chattering_reading_does_not_toggle_the_state_within_the_debounce() {
        // 1 ms readings, 5 ms debounce: a landing whose force chatters for 4 ms is taken as
        // loaded only after five loaded readings in a row, and one unloaded reading then
        // does not lift it.
        let readings = [
            true, false, true, true, false, true, true, true, true, true, false, true,
        ];
        let states = debounced(&readings, 0.001, 0.005);
        let expected = [
            false, false, false, false, false, false, false, false, false, true, true, true,
        ];
        assert_eq!(states, expected);
    }
}
