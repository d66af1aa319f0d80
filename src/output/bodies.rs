//! `bodies.csv`: one row per floating solid per step (`solver::floating`): time, the centre of
//! mass, its velocity, the orientation (2D the angle about z, 3D the unit quaternion), the
//! angular velocity, the fluid's force on the body over the step, and the force of its contact
//! with the fixed solids at the step's last stage (`boundary::contact`) with the pairs that
//! carry it.

use super::OutputError;
use super::csv::{CsvTable, CsvValue, force_unit};
use crate::boundary::contact::ContactLoad;
use crate::boundary::rigid_body::BodyState;
use std::path::Path;

/// The header columns of a `dimension`-D run.
pub fn body_columns(dimension: usize) -> Vec<String> {
    let axes = &["x", "y", "z"][..dimension.clamp(2, 3)];
    let unit = force_unit(dimension);
    let mut c = vec!["t_s".to_string(), "solid".to_string()];
    c.extend(axes.iter().map(|a| format!("{a}_m")));
    c.extend(axes.iter().map(|a| format!("v{a}_m_per_s")));
    if dimension == 2 {
        c.push("angle_rad".into());
        c.push("omega_z_rad_per_s".into());
    } else {
        c.extend(["qw", "qx", "qy", "qz"].map(String::from));
        c.extend(axes.iter().map(|a| format!("omega_{a}_rad_per_s")));
    }
    c.extend(axes.iter().map(|a| format!("f{a}_{unit}")));
    c.extend(axes.iter().map(|a| format!("contact_f{a}_{unit}")));
    c.push("contact_pairs".into());
    c
}

/// `bodies.csv` of a run (module doc).
pub struct BodyLog {
    table: CsvTable,
    dimension: usize,
}

impl BodyLog {
    /// Creates `path` (which must not exist) with the header of a `dimension`-D run.
    pub fn create(path: &Path, dimension: usize) -> Result<Self, OutputError> {
        let columns = body_columns(dimension);
        let columns: Vec<&str> = columns.iter().map(String::as_str).collect();
        Ok(Self {
            table: CsvTable::create(path, &columns)?,
            dimension,
        })
    }

    /// Reopens `path` at its length `len` at a checkpoint ([`CsvTable::resume`]).
    pub fn resume(path: &Path, dimension: usize, len: u64) -> Result<Self, OutputError> {
        let columns = body_columns(dimension);
        let columns: Vec<&str> = columns.iter().map(String::as_str).collect();
        Ok(Self {
            table: CsvTable::resume(path, &columns, len)?,
            dimension,
        })
    }

    /// Appends the row of body `solid` in state `s` at time `t` [s] with the fluid's force
    /// `force` [N] (2D: [N/m]) and its contact load `contact`.
    pub fn push(
        &mut self,
        t: f64,
        solid: &str,
        s: &BodyState,
        force: [f64; 3],
        contact: &ContactLoad,
    ) -> Result<(), OutputError> {
        let d = self.dimension.clamp(2, 3);
        let mut row = vec![CsvValue::Float(t), CsvValue::Text(solid)];
        row.extend((0..d).map(|k| CsvValue::Float(s.centre[k])));
        row.extend((0..d).map(|k| CsvValue::Float(s.velocity[k])));
        if d == 2 {
            // The rotation about z: the quaternion (cos θ/2, 0, 0, sin θ/2).
            let q = s.orientation.quaternion();
            row.push(CsvValue::Float(2.0 * q.k.atan2(q.w)));
            row.push(CsvValue::Float(s.angular_velocity.z));
        } else {
            let q = s.orientation.quaternion();
            row.extend([q.w, q.i, q.j, q.k].map(CsvValue::Float));
            row.extend((0..3).map(|k| CsvValue::Float(s.angular_velocity[k])));
        }
        row.extend((0..d).map(|k| CsvValue::Float(force[k])));
        row.extend((0..d).map(|k| CsvValue::Float(contact.force[k])));
        row.push(CsvValue::Int(contact.pairs as i64));
        self.table.push_row(&row)
    }

    /// Flushes and returns the file's length [bytes].
    pub fn len_on_disk(&mut self) -> Result<u64, OutputError> {
        self.table.len_on_disk()
    }

    /// Flushes the buffered rows.
    pub fn flush(&mut self) -> Result<(), OutputError> {
        self.table.flush()
    }
}
