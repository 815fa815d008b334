//! The robot's controller stack from `[controller]`: the joint loops, the stiffness
//! identification and its excitation, the observers (`sea_ctrl::robot`), built around a
//! controller at a whole-body period.

use crate::schema::ControllerConfig;
use crate::settings::{ExternalWrench, IdentificationWrenches};

impl ControllerConfig {
    /// `multi_rate`: the joint loops of `controller`'s elastic joints with these settings
    /// (bandwidth, joint stiffness).
    pub fn joint_loop(
        &self,
        controller: &sea_ctrl::MomentumController,
    ) -> sea_ctrl::joint_loop::JointTorqueLoop {
        sea_ctrl::joint_loop::JointTorqueLoop::from_settings(controller, &self.joint_loops)
    }

    /// `identification_excitation_nm`: the excitation of `controller`'s elastic joints, `None`
    /// without one; a joint that is not an elastic joint of the model is an error naming its
    /// key.
    pub fn identification_excitation(
        &self,
        controller: &sea_ctrl::MomentumController,
    ) -> crate::Result<Option<sea_ctrl::excitation::IdentificationExcitation>> {
        if self.excitation.amplitudes_nm.is_empty() {
            return Ok(None);
        }
        let (names, actuation) = (&controller.model().joint_names, controller.actuation());
        let mut amplitudes = vec![0.0; actuation.n_elastic()];
        for (name, &amplitude) in &self.excitation.amplitudes_nm {
            let key = format!("controller.identification_excitation_nm.{name}");
            let Some(j) = names.iter().position(|joint| joint == name) else {
                return Err(crate::Error::config(key, "is not a joint of the model"));
            };
            let Some(e) = actuation.elastic_joints.iter().position(|&k| k == j) else {
                return Err(crate::Error::config(key, "is not an elastic joint"));
            };
            amplitudes[e] = amplitude;
        }
        Ok(Some(
            sea_ctrl::excitation::IdentificationExcitation::from_settings(
                amplitudes,
                &self.excitation,
            ),
        ))
    }

    /// `external_wrench = "observed"`: the observer for the whole-body period `period` [s];
    /// `None` when it is off.
    pub fn external_wrench_observer(
        &self,
        period: f64,
    ) -> Option<sea_ctrl::external_wrench::ExternalWrenchObserver> {
        let settings = &self.wrench_observer;
        (settings.kind == ExternalWrench::Observed).then(|| {
            sea_ctrl::external_wrench::ExternalWrenchObserver::new(period, settings.bandwidth_hz)
        })
    }

    /// `external_wrench = "generalized"`: the observer of what `controller`'s dynamics miss,
    /// at the whole-body period `period` [s]; `None` when it is off.
    pub fn generalized_disturbance_observer(
        &self,
        controller: &sea_ctrl::MomentumController,
        period: f64,
    ) -> Option<sea_ctrl::generalized_disturbance::GeneralizedDisturbanceObserver> {
        let settings = &self.wrench_observer;
        (settings.kind == ExternalWrench::Generalized).then(|| {
            sea_ctrl::generalized_disturbance::GeneralizedDisturbanceObserver::new(
                controller,
                period,
                settings.bandwidth_hz,
            )
        })
    }

    /// The parts of the robot's controller stack around `controller`'s whole-body law
    /// (`sea_ctrl::robot`) ticking every `period` [s]: the joint loops with `multi_rate`
    /// (`joint_loops`), and with them the identification and its excitation; the observer of
    /// `external_wrench`. An excitation joint that is not an elastic joint of the model is an
    /// error naming its key.
    pub fn stack_parts(
        &self,
        controller: &sea_ctrl::MomentumController,
        period: f64,
        joint_loops: bool,
    ) -> crate::Result<sea_ctrl::robot::StackParts> {
        let joint_loop = joint_loops.then(|| self.joint_loop(controller));
        let identifier = joint_loop.as_ref().and_then(|joints| {
            self.stiffness_identifier(controller, joints.estimates())
                .map(|identifier| (identifier, self.identification_wrenches))
        });
        let excitation = match &joint_loop {
            Some(_) => self.identification_excitation(controller)?,
            None => None,
        };
        let disturbance_observer = self
            .generalized_disturbance_observer(controller, period)
            .map(|observer| sea_ctrl::robot::DisturbanceObserverLoop::new(observer, controller));
        Ok(sea_ctrl::robot::StackParts {
            joint_loop,
            identifier,
            excitation,
            external_wrench_observer: self.external_wrench_observer(period),
            disturbance_observer,
        })
    }

    /// `multi_rate` with `stiffness_identification`: the identifier of `controller`'s elastic
    /// stiffnesses from the joint loop's estimates `prior`; `None` when it is off.
    pub fn stiffness_identifier(
        &self,
        controller: &sea_ctrl::MomentumController,
        prior: &[sea_dyn::ElasticParameters],
    ) -> Option<sea_ctrl::stiffness_id::StiffnessIdentifier> {
        // The external-force check needs measured wrenches (module doc of stiffness_id).
        let measured = self.identification_wrenches == IdentificationWrenches::Measured;
        let settings = sea_ctrl::stiffness_id::IdentificationSettings {
            max_external_force: self.identification.max_external_force.filter(|_| measured),
            ..self.identification
        };
        self.stiffness_identification
            .then(|| sea_ctrl::stiffness_id::StiffnessIdentifier::new(controller, prior, settings))
    }
}
