//! The contact lookup table in memory (docs/reference/04-table-files.md §4, §7.4): quasi-static contact
//! geometry of a wheelset on straight track, tabulated against its lateral
//! shift y (and optionally its yaw), for one wheel/rail profile pair. Built
//! by the pre-processor, read and written by [`crate::io::schema`], and
//! interpolated linearly at run time when a scene asks for table contact.
//!
//! Conventions: y positive to the left (the left wheel's flange approaches
//! its rail for y > 0); Δr = r_left − r_right; profile coordinates are those
//! of the profile files (before mirroring for the left side), in metres.

use crate::geometry::track::grid::{UniformGrid, lerp, within};

/// One zone (tread or flange) of one wheel in one table row. Absent zones
/// (no candidate) are `None`.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ZoneEntry {
    /// Contact point on the wheel profile, file coordinates (m).
    pub y_wheel_m: f64,
    pub z_wheel_m: f64,
    /// Contact point on the rail profile, file coordinates (m).
    pub y_rail_m: f64,
    pub z_rail_m: f64,
    /// Rolling radius (m).
    pub rolling_radius_m: f64,
    /// Contact angle, positive towards the track centre (rad).
    pub contact_angle_rad: f64,
    /// Penetration δ (m); negative = gap.
    pub penetration_m: f64,
    /// Principal curvatures (1/m), docs/reference/07-contact-forces.md §7.1 sign rule (convex positive).
    pub wheel_rolling_curvature_1_m: f64,
    pub wheel_lateral_curvature_1_m: f64,
    pub rail_rolling_curvature_1_m: f64,
    pub rail_lateral_curvature_1_m: f64,
    /// Hertzian normal force (N); 0 for rigid tables.
    pub normal_force_n: f64,
    /// Angle of the contact point about the axle, positive ahead (rad).
    pub s_wheel_rad: f64,
    /// Lead of the contact point ahead of the axle (m).
    pub lead_m: f64,
}

/// The zone names of a table, in column order.
pub const ZONE_FIELDS: [&str; 14] = [
    "y_wheel",
    "z_wheel",
    "y_rail",
    "z_rail",
    "rolling_radius",
    "contact_angle",
    "penetration",
    "kw_roll",
    "kw_lat",
    "kr_roll",
    "kr_lat",
    "normal_force",
    "s_wheel",
    "lead",
];

/// Units of [`ZONE_FIELDS`].
pub const ZONE_UNITS: [&str; 14] = [
    "m", "m", "m", "m", "m", "rad", "m", "1/m", "1/m", "1/m", "1/m", "N", "rad", "m",
];

impl ZoneEntry {
    /// The values of [`ZONE_FIELDS`].
    pub fn to_values(&self) -> [f64; 14] {
        [
            self.y_wheel_m,
            self.z_wheel_m,
            self.y_rail_m,
            self.z_rail_m,
            self.rolling_radius_m,
            self.contact_angle_rad,
            self.penetration_m,
            self.wheel_rolling_curvature_1_m,
            self.wheel_lateral_curvature_1_m,
            self.rail_rolling_curvature_1_m,
            self.rail_lateral_curvature_1_m,
            self.normal_force_n,
            self.s_wheel_rad,
            self.lead_m,
        ]
    }

    /// An entry from the values of [`ZONE_FIELDS`]; `None` when they are NaN
    /// (the zone had no candidate).
    pub fn from_values(v: &[f64]) -> Option<Self> {
        if v.iter().any(|x| x.is_nan()) {
            return None;
        }
        Some(Self {
            y_wheel_m: v[0],
            z_wheel_m: v[1],
            y_rail_m: v[2],
            z_rail_m: v[3],
            rolling_radius_m: v[4],
            contact_angle_rad: v[5],
            penetration_m: v[6],
            wheel_rolling_curvature_1_m: v[7],
            wheel_lateral_curvature_1_m: v[8],
            rail_rolling_curvature_1_m: v[9],
            rail_lateral_curvature_1_m: v[10],
            normal_force_n: v[11],
            s_wheel_rad: v[12],
            lead_m: v[13],
        })
    }
}

/// One row: the wheelset at lateral shift `y_m` and yaw `yaw_rad`.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ContactTableRow {
    /// Lateral shift of the wheelset centre, positive left (m).
    pub y_m: f64,
    /// Yaw, positive turning the nose left (rad).
    pub yaw_rad: f64,
    /// Height of the wheelset centre above the track plane (m).
    pub height_m: f64,
    /// Roll, positive raising the left wheel (rad).
    pub roll_rad: f64,
    /// Rolling radius difference r_left − r_right at the main contacts (m).
    pub delta_r_m: f64,
    /// `[left, right][tread, flange]`.
    pub zones: [[Option<ZoneEntry>; 2]; 2],
}

/// Parameters a table was built with.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct ContactTableMeta {
    /// Profile files as given.
    pub wheel_profile: String,
    pub rail_profile: String,
    /// Nominal rolling radius (m), back-to-back (m), gauge (m), rail spacing
    /// (m), rail inclination (rad).
    pub wheel_radius_m: f64,
    pub back_to_back_m: f64,
    pub gauge_m: f64,
    pub rail_spacing_m: f64,
    pub rail_inclination_rad: f64,
    /// The rail profile's digest and carried cant (`None` for tables
    /// written before they were recorded).
    pub rail_record: Option<crate::geometry::profile::rail_cant::RailProfileRecord>,
    /// "rigid" or "elastic".
    pub support: String,
    /// Vertical load per wheel for elastic tables (N); 0 for rigid.
    pub wheel_load_n: f64,
    /// Material of elastic tables.
    pub young_pa: f64,
    pub poisson: f64,
    /// Where the table came from ("track-preproc", "rsgeo import", …).
    pub source: String,
}

/// Equivalent conicity (EN 15302) of the table's wheel/rail pair, with the
/// Δr function it was computed from: that of EN 15302's idealised wheelset,
/// kept level and each wheel lowered onto its rail (the standard's reference
/// results neglect the roll; the table's rows do not).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct ConicityTable {
    pub amplitude_m: Vec<f64>,
    /// tan γe; NaN where the amplitude exceeds the table.
    pub tan_gamma_e: Vec<f64>,
    /// The level wheelset's Δr(y) (m) on the table's lateral grid.
    pub level_y_m: Vec<f64>,
    pub level_delta_r_m: Vec<f64>,
}

/// A contact lookup table.
#[derive(Debug, Clone, PartialEq)]
pub struct ContactTable {
    pub meta: ContactTableMeta,
    /// Lateral shift grid, increasing, uniform (m).
    pub y_m: Vec<f64>,
    /// Yaw grid, increasing (rad); `[0.0]` without yaw.
    pub yaw_rad: Vec<f64>,
    /// Rows, y-major: row `iy * yaw.len() + iyaw`.
    pub rows: Vec<ContactTableRow>,
    pub conicity: ConicityTable,
}

/// Errors of a table look-up.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ContactTableError {
    #[error("lateral shift {y_m} m is outside the contact table ({min_m} … {max_m} m)")]
    OutOfRange { y_m: f64, min_m: f64, max_m: f64 },
    #[error("contact table is malformed: {0}")]
    Malformed(String),
}

impl ContactTable {
    /// Check the grids and the row count.
    pub fn validate(&self) -> Result<(), ContactTableError> {
        let bad = |m: String| Err(ContactTableError::Malformed(m));
        if self.y_m.len() < 2 || self.yaw_rad.is_empty() {
            return bad("needs at least 2 lateral shifts and 1 yaw".into());
        }
        if self.rows.len() != self.y_m.len() * self.yaw_rad.len() {
            return bad(format!(
                "{} rows for {} × {} grid points",
                self.rows.len(),
                self.y_m.len(),
                self.yaw_rad.len()
            ));
        }
        if !self.y_m.windows(2).all(|w| w[1] > w[0])
            || !self.yaw_rad.windows(2).all(|w| w[1] > w[0])
        {
            return bad("grids must increase".into());
        }
        Ok(())
    }

    /// The row at grid indices.
    pub fn row(&self, iy: usize, iyaw: usize) -> &ContactTableRow {
        &self.rows[iy * self.yaw_rad.len() + iyaw]
    }

    /// Index of the yaw-0 column (or the one nearest to it).
    pub fn zero_yaw_index(&self) -> usize {
        self.yaw_rad
            .iter()
            .enumerate()
            .min_by(|a, b| a.1.abs().total_cmp(&b.1.abs()))
            .map_or(0, |(i, _)| i)
    }

    /// Δr(y) at zero yaw: (y, Δr) pairs (m).
    pub fn delta_r_curve(&self) -> Vec<(f64, f64)> {
        let j = self.zero_yaw_index();
        (0..self.y_m.len())
            .map(|i| (self.y_m[i], self.row(i, j).delta_r_m))
            .collect()
    }

    /// Interval and fraction of `y_m` in the lateral grid
    /// ([`crate::geometry::track::grid`]; the interval is that of a search of the
    /// grid, O(1) on the uniform grids the pre-processor writes). Outside
    /// the grid (no slack) or NaN: out of range; fewer than 2 shifts or
    /// shifts that do not increase: malformed.
    fn locate_y(&self, y_m: f64) -> Result<(usize, f64), ContactTableError> {
        let n = self.y_m.len();
        let (Some(&lo), Some(&hi)) = (self.y_m.first(), self.y_m.last()) else {
            return Err(ContactTableError::Malformed("no lateral shifts".into()));
        };
        let grid = UniformGrid::spanning(lo, hi, n).ok_or_else(|| {
            ContactTableError::Malformed(format!(
                "{n} lateral shifts from {lo} to {hi} m: needs at least 2, increasing"
            ))
        })?;
        if !within(y_m, lo, hi, 0.0) {
            return Err(ContactTableError::OutOfRange {
                y_m,
                min_m: lo,
                max_m: hi,
            });
        }
        Ok(grid.locate(y_m, |k| self.y_m[k]))
    }

    /// Height, roll and Δr at lateral shift `y_m` and zero yaw, by linear
    /// interpolation: `(height_m, roll_rad, delta_r_m)`.
    pub fn wheelset_at(&self, y_m: f64) -> Result<(f64, f64, f64), ContactTableError> {
        let (i, f) = self.locate_y(y_m)?;
        let j = self.zero_yaw_index();
        let (a, b) = (self.row(i, j), self.row(i + 1, j));
        let l = |x, y| lerp(f, x, y);
        Ok((
            l(a.height_m, b.height_m),
            l(a.roll_rad, b.roll_rad),
            l(a.delta_r_m, b.delta_r_m),
        ))
    }

    /// A zone's entry at lateral shift `y_m` and zero yaw, linearly
    /// interpolated; `None` when either neighbouring row lacks the zone.
    pub fn zone_at(
        &self,
        y_m: f64,
        wheel: usize,
        zone: usize,
    ) -> Result<Option<ZoneEntry>, ContactTableError> {
        let (i, f) = self.locate_y(y_m)?;
        let j = self.zero_yaw_index();
        let (Some(a), Some(b)) = (
            self.row(i, j).zones[wheel][zone],
            self.row(i + 1, j).zones[wheel][zone],
        ) else {
            return Ok(None);
        };
        let (va, vb) = (a.to_values(), b.to_values());
        let v: Vec<f64> = va.iter().zip(&vb).map(|(&x, &y)| lerp(f, x, y)).collect();
        Ok(ZoneEntry::from_values(&v))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Height 0.4 + y, roll 2y, Δr 3y on y = −0.01 … 0.01 every 1 mm.
    fn table(n: usize) -> ContactTable {
        let y_m: Vec<f64> = (0..n).map(|i| -0.01 + 1e-3 * i as f64).collect();
        let rows = y_m
            .iter()
            .map(|&y| ContactTableRow {
                y_m: y,
                height_m: 0.4 + y,
                roll_rad: 2.0 * y,
                delta_r_m: 3.0 * y,
                ..Default::default()
            })
            .collect();
        ContactTable {
            meta: ContactTableMeta::default(),
            y_m,
            yaw_rad: vec![0.0],
            rows,
            conicity: ConicityTable::default(),
        }
    }

    #[test]
    fn lookups_interpolate_inside_and_refuse_outside_the_grid() {
        let t = table(21);
        t.validate().unwrap();
        for y in [-0.01, -0.0042, 0.0, 0.003, 0.01] {
            let (h, r, d) = t.wheelset_at(y).unwrap();
            assert!((h - (0.4 + y)).abs() < 1e-15, "{y}");
            assert!((r - 2.0 * y).abs() < 1e-15 && (d - 3.0 * y).abs() < 1e-15);
        }
        for y in [-0.0100001, 0.0100001, f64::NAN, f64::INFINITY] {
            assert!(
                matches!(
                    t.wheelset_at(y),
                    Err(ContactTableError::OutOfRange { min_m, max_m, .. })
                        if min_m == -0.01 && (max_m - 0.01).abs() < 1e-15
                ),
                "{y}"
            );
        }
        assert!(t.zone_at(0.02, 0, 0).is_err());
        assert_eq!(t.zone_at(0.0, 0, 0), Ok(None));
    }

    #[test]
    fn too_short_or_decreasing_grids_are_malformed_not_a_panic() {
        for n in [0, 1] {
            let t = table(n);
            assert!(matches!(
                t.wheelset_at(-0.01),
                Err(ContactTableError::Malformed(_))
            ));
        }
        let mut t = table(5);
        t.y_m.reverse();
        assert!(matches!(
            t.wheelset_at(0.0),
            Err(ContactTableError::Malformed(_))
        ));
    }
}
