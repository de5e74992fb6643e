//! What a run needs of the model (`SceneNeeds`): a scene's declaration (`studies::scenes`) or the FMU's run
//! (`SceneNeeds::of_run`), which decides its pruned configuration. Here in `sim` because the FMU's library
//! (built without the `studies` feature) reads it.

use super::{Channel, RoadChoice, SpeedMode};
use crate::model::tire::SlipModel;

/// What a scene needs of the model: the one place that decides its pruned configuration
/// (`Scene::config_for`, `Scene::columns`). What it does not name is left out: the states of the other
/// slip model and speed mode (`model::vehicle::Layout`), the output evaluation at each output point
/// when every channel it reads comes straight from the state, and the CSV columns it does not read
/// (but those of the state). Leaving them out is exact
/// (tests/pruning.rs); docs/results.md gives the cost with and without.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SceneNeeds {
    /// Live inputs besides the rack profile: wheel drive and brake torques. No scene drives them; a run
    /// that adds them (`rtv scene --brake`, `--drive`) makes them live (`with_torques`).
    pub torques: bool,
    pub road: RoadChoice,
    /// The slip model and the speed mode (docs/physics.md §8.2: hold for every scene, relaxation slip); they
    /// decide the states.
    pub slip: SlipModel,
    pub speed_mode: SpeedMode,
    /// The output channels its summary and its plot read (docs/physics.md §8.3, scripts/plot_scenes.py).
    pub outputs: &'static [Channel],
    /// Whether the run watches the physical events (a wheel off the road, locked or spun up: `Events`),
    /// which are seen only by the output evaluation. The bump course can lift a wheel and torques can
    /// lock or spin one; on a level road with the rack alone the sine lifts none (tests/pruning.rs
    /// checks that the full run records none; nor with the paper's amplitude or 15 mm of rack, by
    /// `rtv scene sine --keep-all --amplitude 0.015`).
    pub events: bool,
}

impl SceneNeeds {
    /// The needs of a run that is not one of the scenes (the FMU's): its configuration gives the road, the
    /// slip model and the speed mode; `torques` says whether wheel torques are live; the outputs are served
    /// when read (none declared here). The physical events are watched where they can happen: on a road
    /// with bumps (a wheel leaves the road) and with torques live (a wheel locks or spins up).
    pub fn of_run(config: &super::SimConfig, torques: bool) -> SceneNeeds {
        SceneNeeds {
            torques,
            road: config.road,
            slip: config.options.slip,
            speed_mode: config.options.speed_mode,
            outputs: &[],
            events: torques || config.road != RoadChoice::Flat,
        }
    }

    /// The needs with wheel torques live (and so the events they cause watched).
    pub fn with_torques(self) -> SceneNeeds {
        SceneNeeds { torques: true, events: true, ..self }
    }

    /// Whether a run needs the model evaluated at its output points: for an output that is not read
    /// straight from the state, or to watch the events.
    pub fn evaluates_outputs(&self) -> bool {
        self.events || self.outputs.iter().any(|channel| !channel.from_state())
    }
}
