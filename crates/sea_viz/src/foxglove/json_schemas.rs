//! The JSON Schemas of the JSON channels (one per `Topic` encoded as JSON), as Foxglove
//! reads them to name and check the fields of each message.

pub(super) const COM_SCHEMA: &str = r#"{
  "title": "sea_momentum.Com",
  "description": "Centre of mass, its reference and the tracking error com - reference (world axes, m)",
  "type": "object",
  "properties": {
    "com": { "type": "array", "items": { "type": ["number", "null"] }, "minItems": 3, "maxItems": 3 },
    "reference": { "type": "array", "items": { "type": ["number", "null"] }, "minItems": 3, "maxItems": 3 },
    "error": { "type": "array", "items": { "type": ["number", "null"] }, "minItems": 3, "maxItems": 3 }
  },
  "required": ["com", "reference", "error"]
}"#;

pub(super) const MOMENTUM_SCHEMA: &str = r#"{
  "title": "sea_momentum.Momentum",
  "description": "Centroidal momentum: linear m pdot_com (kg m/s) and angular L_com (kg m^2/s), world axes; the external wrench the controller took (force N, moment about the CoM N m; zeros without an observer)",
  "type": "object",
  "properties": {
    "linear": { "type": "array", "items": { "type": ["number", "null"] }, "minItems": 3, "maxItems": 3 },
    "angular": { "type": "array", "items": { "type": ["number", "null"] }, "minItems": 3, "maxItems": 3 },
    "external_wrench": { "type": "array", "items": { "type": ["number", "null"] }, "minItems": 6, "maxItems": 6 }
  },
  "required": ["linear", "angular", "external_wrench"]
}"#;

pub(super) const JOINT_STATE_SCHEMA: &str = r#"{
  "title": "sea_momentum.JointState",
  "description": "Joint positions (rad or m), velocities (rad/s or m/s) and torques (Nm or N), in coordinate order",
  "type": "object",
  "properties": {
    "names": { "type": "array", "items": { "type": "string" } },
    "position": { "type": "array", "items": { "type": ["number", "null"] } },
    "velocity": { "type": "array", "items": { "type": ["number", "null"] } },
    "torque": { "type": "array", "items": { "type": ["number", "null"] } }
  },
  "required": ["names", "position", "velocity", "torque"]
}"#;

pub(super) const MOTOR_STATE_SCHEMA: &str = r#"{
  "title": "sea_momentum.MotorState",
  "description": "Motor angles (rad), velocities and desired velocities (rad/s) of the elastic joints, motor torques (Nm)",
  "type": "object",
  "properties": {
    "names": { "type": "array", "items": { "type": "string" } },
    "position": { "type": "array", "items": { "type": ["number", "null"] } },
    "velocity": { "type": "array", "items": { "type": ["number", "null"] } },
    "velocity_desired": { "type": "array", "items": { "type": ["number", "null"] } },
    "torque": { "type": "array", "items": { "type": ["number", "null"] } }
  },
  "required": ["names", "position", "velocity", "velocity_desired", "torque"]
}"#;

pub(super) const CONTACT_WRENCHES_SCHEMA: &str = r#"{
  "title": "sea_momentum.ContactWrenches",
  "description": "Contact wrenches: force (N) and moment (Nm) of each contact, world axes",
  "type": "object",
  "properties": {
    "contacts": {
      "type": "array",
      "items": {
        "type": "object",
        "properties": {
          "frame": { "type": "string", "description": "Contact frame (URDF link)" },
          "force": { "type": "array", "items": { "type": ["number", "null"] }, "minItems": 3, "maxItems": 3 },
          "moment": { "type": "array", "items": { "type": ["number", "null"] }, "minItems": 3, "maxItems": 3 }
        },
        "required": ["frame", "force", "moment"]
      }
    }
  },
  "required": ["contacts"]
}"#;

pub(super) const QP_STATUS_SCHEMA: &str = r#"{
  "title": "sea_momentum.QpStatus",
  "description": "Status of the contact-wrench QP and the number of failures so far",
  "type": "object",
  "properties": {
    "status": { "type": "string" },
    "failures": { "type": "integer", "minimum": 0 }
  },
  "required": ["status", "failures"]
}"#;

pub(super) const BASE_POSE_SCHEMA: &str = r#"{
  "title": "sea_momentum.BasePose",
  "description": "Floating base: position (m), orientation quaternion (w, x, y, z), linear (m/s) and angular (rad/s) velocity, world axes",
  "type": "object",
  "properties": {
    "position": { "type": "array", "items": { "type": ["number", "null"] }, "minItems": 3, "maxItems": 3 },
    "orientation_wxyz": { "type": "array", "items": { "type": ["number", "null"] }, "minItems": 4, "maxItems": 4 },
    "linear_velocity": { "type": "array", "items": { "type": ["number", "null"] }, "minItems": 3, "maxItems": 3 },
    "angular_velocity": { "type": "array", "items": { "type": ["number", "null"] }, "minItems": 3, "maxItems": 3 }
  },
  "required": ["position", "orientation_wxyz", "linear_velocity", "angular_velocity"]
}"#;

pub(super) const DISTURBANCES_SCHEMA: &str = r#"{
  "title": "sea_momentum.Disturbances",
  "description": "The external wrench of each [[disturbances]] entry from this sample on: force (N) and torque (Nm), world axes at the link origin, zero when inactive",
  "type": "object",
  "properties": {
    "disturbances": {
      "type": "array",
      "items": {
        "type": "object",
        "properties": {
          "link": { "type": "string", "description": "The link pushed (URDF link)" },
          "active": { "type": "boolean" },
          "force": { "type": "array", "items": { "type": ["number", "null"] }, "minItems": 3, "maxItems": 3 },
          "torque": { "type": "array", "items": { "type": ["number", "null"] }, "minItems": 3, "maxItems": 3 }
        },
        "required": ["link", "active", "force", "torque"]
      }
    }
  },
  "required": ["disturbances"]
}"#;

pub(super) const CONTACT_POINTS_SCHEMA: &str = r#"{
  "title": "sea_momentum.ContactPoints",
  "description": "Unilateral contacts: each contact point's position (m) and force on its foot (N), world axes, and whether it carries a force",
  "type": "object",
  "properties": {
    "points": {
      "type": "array",
      "items": {
        "type": "object",
        "properties": {
          "contact": { "type": "string", "description": "Contact frame (URDF link) of the point's foot" },
          "index": { "type": "integer", "minimum": 0, "description": "The point's index in its foot" },
          "active": { "type": "boolean", "description": "Whether it carries a force (touches the ground)" },
          "position": { "type": "array", "items": { "type": ["number", "null"] }, "minItems": 3, "maxItems": 3 },
          "force": { "type": "array", "items": { "type": ["number", "null"] }, "minItems": 3, "maxItems": 3 }
        },
        "required": ["contact", "index", "active", "position", "force"]
      }
    }
  },
  "required": ["points"]
}"#;

pub(super) const CONTACT_CHECK_SCHEMA: &str = r#"{
  "title": "sea_momentum.ContactCheck",
  "description": "Unilateral contacts, a diagnostic: each foot's delivered wrench (sole frame) checked against a unilateral contact with friction on its sole rectangle; a check is violated beyond its bound by more than 1e-6 (N, friction ratio, m); the friction ratio and the centre of pressure are null (not checked) when the normal force is not positive",
  "type": "object",
  "properties": {
    "contacts": {
      "type": "array",
      "items": {
        "type": "object",
        "properties": {
          "contact": { "type": "string", "description": "Contact frame (URDF link) of the foot" },
          "violated": { "type": ["string", "null"], "description": "The first constraint violated (normal_force, friction, center_of_pressure), null when none is" },
          "checks": {
            "type": "array",
            "items": {
              "type": "object",
              "properties": {
                "constraint": { "type": "string", "enum": ["normal_force", "friction", "center_of_pressure_x", "center_of_pressure_y"] },
                "value": { "type": ["number", "null"], "description": "f_z (N), |f_t| / f_z, or the CoP coordinate (m), sole frame" },
                "lower": { "type": ["number", "null"], "description": "The lower bound (null: none)" },
                "upper": { "type": ["number", "null"], "description": "The upper bound (null: none)" },
                "violated": { "type": "boolean" }
              },
              "required": ["constraint", "value", "lower", "upper", "violated"]
            }
          }
        },
        "required": ["contact", "violated", "checks"]
      }
    }
  },
  "required": ["contacts"]
}"#;
