//! Loading the reference data generated with YADE, LAMMPS and LIGGGHTS (plain CSV with a
//! header row, no quoting; parameter files as JSON).
#![allow(dead_code)]

use nalgebra::Vector3;
use std::collections::BTreeMap;
use std::path::Path;

/// One CSV row: column name -> text.
#[derive(Clone, Debug)]
pub struct Row(pub BTreeMap<String, String>);

impl Row {
    pub fn f(&self, column: &str) -> f64 {
        let text = self
            .0
            .get(column)
            .unwrap_or_else(|| panic!("no column {column}"));
        text.parse()
            .unwrap_or_else(|_| panic!("column {column}: not a number: {text:?}"))
    }
    pub fn s(&self, column: &str) -> &str {
        &self.0[column]
    }
    /// A vector from three columns named by `pattern` with `{}` replaced by x, y, z.
    pub fn v(&self, pattern: &str) -> Vector3<f64> {
        let c = |a: &str| self.f(&pattern.replace("{}", a));
        Vector3::new(c("x"), c("y"), c("z"))
    }
}

/// Rows grouped by the `case` column, in file order within each case.
pub fn load_cases(path: &Path) -> BTreeMap<String, Vec<Row>> {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut lines = text.lines();
    let header: Vec<String> = lines
        .next()
        .unwrap()
        .split(',')
        .map(str::to_owned)
        .collect();
    let mut cases: BTreeMap<String, Vec<Row>> = BTreeMap::new();
    for line in lines.filter(|l| !l.is_empty()) {
        let row: BTreeMap<String, String> = header
            .iter()
            .cloned()
            .zip(line.split(',').map(str::to_owned))
            .collect();
        cases.entry(row["case"].clone()).or_default().push(Row(row));
    }
    cases
}

pub fn load_json(path: &Path) -> serde_json::Value {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    serde_json::from_str(&text).unwrap()
}

pub fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}
