//! Foxglove channels of a run, built with the Foxglove SDK (`foxglove` crate): written to an
//! MCAP file by [`crate::mcap_log`] and served live by [`live`].
//!
//! | topic               | encoding | schema                          | content                                         |
//! |---------------------|----------|---------------------------------|-------------------------------------------------|
//! | `/tf`               | protobuf | `foxglove.FrameTransforms`      | `world_H_link` of every URDF link               |
//! | `/robot` (once)     | protobuf | `foxglove.SceneUpdate`          | robot bodies: URDF boxes, cylinders, spheres, meshes |
//! | `/scene`            | protobuf | `foxglove.SceneUpdate`          | support polygon, CoM, wrenches, pushes; `[walking]`: footsteps, swing path, DCM, VRP |
//! | `/com`              | json     | `sea_momentum.Com`              | CoM, its reference, `error = com - ref`         |
//! | `/momentum`         | json     | `sea_momentum.Momentum`         | centroidal momentum `[m pdot_com; L_com]`       |
//! | `/joints`           | json     | `sea_momentum.JointState`       | `s`, `sdot`, joint torques                      |
//! | `/motors`           | json     | `sea_momentum.MotorState`       | `theta`, `thetadot` (+ desired), torques        |
//! | `/contact_wrenches` | json     | `sea_momentum.ContactWrenches`  | force and moment of each contact                |
//! | `/qp`               | json     | `sea_momentum.QpStatus`         | QP status and failure count                     |
//! | `/base`             | json     | `sea_momentum.BasePose`         | base position, quaternion, velocities           |
//! | `/disturbances`     | json     | `sea_momentum.Disturbances`     | each `[[disturbances]]` push: link, force, torque |
//! | `/planned_wrenches` | json     | `sea_momentum.ContactWrenches`  | the wrench the controller's QP planned for each contact |
//! | `/contact_points`   | json     | `sea_momentum.ContactPoints`    | unilateral contacts only: each point's contact, position, force, activity |
//! | `/contact_check`    | json     | `sea_momentum.ContactCheck`     | unilateral contacts only: each foot's contact check of its delivered wrench (constraint, value, bounds, verdict) |
//! | `/events`           | protobuf | `foxglove.Log`                  | a fall (time, foot, constraint, value, bound); each impact ([`sea_loop::impacts`]); unilateral contacts: each change of a foot's contact check; `[walking]`: planned lift-offs and touchdowns, measured lift-offs |
//!
//! Why two encodings: the SDK's typed messages (`foxglove::messages`) are protobuf messages
//! with their descriptors as schemas, so `/tf` and `/scene` use them as they are, no copied
//! schema to keep in step; protobuf is what Foxglove decodes fastest, it is several times
//! smaller than JSON for the 41 link poses of every sample, and the `mcap` Python reader
//! decodes it with `mcap-protobuf-support`. Our own channels stay JSON with a JSON Schema: no
//! SDK type fits them, JSON needs no decoder package to read back (`json.loads`), and
//! Foxglove plots JSON fields by path (`/com.error[0]`) just as protobuf ones.
//!
//! `/robot` and `/scene` draw the robot with no setup: `/robot`, written once (at the first
//! sample; see [`scene`] for why and for seeking), has one frame-locked entity per link with the
//! URDF's boxes, cylinders, spheres and meshes (`frame_id` = link name, as in `/tf`); `/scene`
//! has the foot rectangle of each contact as a closed line in the sole frame (the support
//! polygon), the CoM and its reference as spheres, the contact forces as arrows at the soles,
//! and each `[[disturbances]]` push as a blue arrow ending at its link (zero length while it
//! is off), in the `world` frame; under unilateral contacts also the entity `contact_points`
//! (a sphere per point, green while it carries force, and an arrow along its force); under
//! `[walking]` the walk's entities `walking/*` (module `walking`).
//! Units are SI, axes are world axes, `log_time = publish_time = time_s` in nanoseconds.
//! Non-finite numbers (a diverged run) are JSON `null`; a `/tf` or `/scene` message is skipped
//! when a pose in it is not finite, since Foxglove needs numbers there.

mod channels;
mod json_schemas;
pub mod live;
pub mod scene;
mod walking;

pub use channels::{nanoseconds, SampleEncoder, Topic};
pub(crate) use scene::StaticScene;
pub use scene::{FootRectangle, SceneSource, ARROW_M_PER_N};

/// The topic of the robot's bodies (`foxglove.SceneUpdate`, one message per log).
pub const ROBOT_TOPIC: &str = "/robot";

/// The fixed frame: parent of every link in `/tf`, frame of the CoM and wrench markers.
pub const WORLD_FRAME: &str = "world";
