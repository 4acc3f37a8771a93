//! A study's results as one table: a row per case with its number, the
//! factors, the responses, what the summary says of its own numbers
//! (`dt_auto`, each segment's `stationary`, `warning_count`, `warnings`),
//! its status, wall time and error. Written as CSV and (feature `parquet`)
//! as Parquet, and drawn (feature `figures`) as a main-effects figure per
//! response.
//!
//! Factors are named as the plan wrote their paths (`sprockets.0.speed_rpm`
//! stays so). Responses are the summary's numeric fields as dotted paths,
//! arrays indexed from 0 (`segments.0.mean_link_force_n`), except the list
//! of tooth jumps: its first jump's fields and `tooth_jump_count`, and of the
//! tip rides: their sum, `tip_ride_count`. A case that
//! failed or has not finished has no responses nor flags (null); its status
//! says why. A finished case with a warning, or with a segment that is not
//! stationary, is `warned`, not `ok`: `df[df.status == "ok"]` keeps the
//! cases whose numbers stand as they are.
//!
//! This module reads the cases' files; it runs nothing.

use super::{CaseStatus, Responses, StudyDir, StudyError};

/// A column's values; `None` is null.
#[derive(Clone, Debug, PartialEq)]
pub enum ColumnData {
    /// 64-bit integers, never null (the case number).
    Int(Vec<i64>),
    /// Counts, 64-bit integers.
    Count(Vec<Option<i64>>),
    /// Booleans (`true`, `false` in the CSV).
    Bool(Vec<Option<bool>>),
    /// Numbers.
    Float(Vec<Option<f64>>),
    /// Text.
    Text(Vec<Option<String>>),
}

/// A named column.
#[derive(Clone, Debug, PartialEq)]
pub struct Column {
    /// Its name: `case`, a factor's path as the plan wrote it, a
    /// response's path, `dt_auto`, `segments.<k>.stationary`,
    /// `warning_count`, `warnings`, `status`, `case_wall_s`, `error`.
    pub name: String,
    /// Its values, one per case.
    pub data: ColumnData,
}

/// The merged results.
#[derive(Clone, Debug, PartialEq)]
pub struct Table {
    /// Columns, all of the same length.
    pub columns: Vec<Column>,
    /// How many of the columns (after `case`) are factors.
    pub factors: usize,
    /// How many (after the factors) are responses.
    pub responses: usize,
}

/// The numeric leaves of a summary as (dotted path, value); booleans and
/// text are left out. Of the list of tooth jumps only the first jump's
/// fields (`tooth_jumps.0.t_s`, …) are kept, and `tooth_jump_count` (0
/// where the summary lists none) says how many there were: a column per
/// jump would grow the table with every jump. Of the tip rides (one entry
/// per sprocket whose tips were ridden) only their sum is kept,
/// `tip_ride_count`.
pub(crate) fn numeric_fields(value: &serde_json::Value) -> Vec<(String, f64)> {
    let mut out = numeric_leaves(value);
    out.retain(|(name, _)| !is_later_jump(name) && !name.starts_with("tip_rides."));
    let jumps = value
        .get("tooth_jumps")
        .and_then(serde_json::Value::as_array)
        .map_or(0, Vec::len);
    out.push((TOOTH_JUMP_COUNT.to_owned(), jumps as f64));
    let rides: f64 = value
        .get("tip_rides")
        .and_then(serde_json::Value::as_array)
        .map_or(0.0, |rides| {
            rides
                .iter()
                .filter_map(|r| r.get("count").and_then(serde_json::Value::as_f64))
                .sum()
        });
    out.push((TIP_RIDE_COUNT.to_owned(), rides));
    out
}

/// The response that counts a case's tooth jumps.
const TOOTH_JUMP_COUNT: &str = "tooth_jump_count";

/// The response that counts a case's tip rides.
const TIP_RIDE_COUNT: &str = "tip_ride_count";

/// A field of the second or a later tooth jump (`tooth_jumps.1.t_s`).
fn is_later_jump(name: &str) -> bool {
    name.strip_prefix("tooth_jumps.")
        .and_then(|rest| rest.split('.').next())
        .is_some_and(|index| index != "0")
}

/// Every numeric leaf of `value` as (dotted path, value).
fn numeric_leaves(value: &serde_json::Value) -> Vec<(String, f64)> {
    fn walk(v: &serde_json::Value, prefix: &str, out: &mut Vec<(String, f64)>) {
        let join = |key: &str| {
            if prefix.is_empty() {
                key.to_owned()
            } else {
                format!("{prefix}.{key}")
            }
        };
        match v {
            serde_json::Value::Number(n) => {
                if let Some(x) = n.as_f64() {
                    out.push((prefix.to_owned(), x));
                }
            }
            serde_json::Value::Object(map) => {
                for (k, v) in map {
                    walk(v, &join(k), out);
                }
            }
            serde_json::Value::Array(items) => {
                for (i, v) in items.iter().enumerate() {
                    walk(v, &join(&i.to_string()), out);
                }
            }
            _ => {}
        }
    }
    let mut out = Vec::new();
    walk(value, "", &mut out);
    out
}

/// What a case's row says of it (`status`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum RowStatus {
    /// Finished, no warning, every segment stationary.
    Ok,
    /// Finished with a warning or a segment that is not stationary: its
    /// numbers are to be doubted (`warnings` says why).
    Warned,
    /// Did not finish (`error` says why).
    Failed,
    /// Not run yet.
    Missing,
}

impl RowStatus {
    /// As written in the table.
    pub(crate) fn name(self) -> &'static str {
        match self {
            Self::Ok => "ok",
            Self::Warned => "warned",
            Self::Failed => "failed",
            Self::Missing => "missing",
        }
    }
}

/// Separates a case's warnings in the `warnings` column.
pub(crate) const WARNING_SEPARATOR: &str = " | ";

/// What the table reads of one case.
struct CaseRow {
    status: Option<CaseStatus>,
    summary: Option<serde_json::Value>,
    fields: Option<Vec<(String, f64)>>,
}

impl CaseRow {
    fn warnings(&self) -> Option<Vec<String>> {
        let list = self.summary.as_ref()?.get("warnings")?.as_array()?;
        Some(
            list.iter()
                .filter_map(|w| w.as_str().map(str::to_owned))
                .collect(),
        )
    }

    /// Segment `k`'s `stationary`, where the summary has it.
    fn stationary(&self, k: usize) -> Option<bool> {
        self.summary
            .as_ref()?
            .get("segments")?
            .get(k)?
            .get("stationary")?
            .as_bool()
    }

    fn segments(&self) -> usize {
        self.summary
            .as_ref()
            .and_then(|s| s.get("segments")?.as_array().map(Vec::len))
            .unwrap_or(0)
    }

    fn row_status(&self) -> RowStatus {
        match &self.status {
            None => RowStatus::Missing,
            Some(s) if !s.ok || self.summary.is_none() => RowStatus::Failed,
            Some(_) => {
                let warned = self.warnings().is_some_and(|w| !w.is_empty())
                    || (0..self.segments()).any(|k| self.stationary(k) == Some(false));
                if warned {
                    RowStatus::Warned
                } else {
                    RowStatus::Ok
                }
            }
        }
    }
}

impl Table {
    /// Merges the cases in `dir`: finished ones with their responses and
    /// flags, failed ones with their error, the rest as `missing`.
    pub fn collect(dir: &StudyDir) -> Result<Self, StudyError> {
        let study = &dir.study;
        let n = study.cases.len();
        let mut rows = Vec::with_capacity(n);
        for k in 0..n {
            let status = dir.status(k)?;
            let summary = match &status {
                Some(s) if s.ok => dir.summary(k)?,
                _ => None,
            };
            let fields = summary.as_ref().map(numeric_fields);
            rows.push(CaseRow {
                status,
                summary,
                fields,
            });
        }
        let names = response_names(&study.responses, &rows)?;

        let mut columns = vec![Column {
            name: "case".to_owned(),
            data: ColumnData::Int((0..n as i64).collect()),
        }];
        for (i, name) in study.factor_names.iter().enumerate() {
            let values: Vec<&toml::Value> = study.cases.iter().map(|c| &c.values[i]).collect();
            columns.push(factor_column(name, &values));
        }
        for name in &names {
            columns.push(Column {
                name: name.clone(),
                data: ColumnData::Float(
                    rows.iter()
                        .map(|r| {
                            r.fields
                                .as_ref()
                                .and_then(|f| f.iter().find(|(n, _)| n == name).map(|(_, x)| *x))
                        })
                        .collect(),
                ),
            });
        }
        columns.extend(flag_columns(&rows));
        columns.push(Column {
            name: "case_wall_s".to_owned(),
            data: ColumnData::Float(
                rows.iter()
                    .map(|r| r.status.as_ref().map(|s| s.wall_s))
                    .collect(),
            ),
        });
        columns.push(Column {
            name: "error".to_owned(),
            data: ColumnData::Text(
                rows.iter()
                    .map(|r| r.status.as_ref().and_then(|s| s.error.clone()))
                    .collect(),
            ),
        });
        Ok(Self {
            columns,
            factors: study.factors.len(),
            responses: names.len(),
        })
    }

    /// Each case's [`RowStatus`], from the `status` column.
    pub(crate) fn statuses(&self) -> Vec<Option<&str>> {
        match self
            .columns
            .iter()
            .find(|c| c.name == "status")
            .map(|c| &c.data)
        {
            Some(ColumnData::Text(v)) => v.iter().map(Option::as_deref).collect(),
            _ => Vec::new(),
        }
    }

    /// Number of rows.
    pub(crate) fn rows(&self) -> usize {
        self.columns.first().map_or(0, |c| match &c.data {
            ColumnData::Int(v) => v.len(),
            ColumnData::Count(v) => v.len(),
            ColumnData::Bool(v) => v.len(),
            ColumnData::Float(v) => v.len(),
            ColumnData::Text(v) => v.len(),
        })
    }

    /// The table as CSV: a header of column names, empty cells for nulls,
    /// numbers in Rust's shortest round-trip form, booleans `true`/`false`.
    ///
    /// # Errors
    ///
    /// Only if the CSV writer fails, which writing to memory does not.
    pub fn to_csv(&self) -> Result<String, StudyError> {
        let failed = |e: &dyn std::fmt::Display| StudyError::Csv(e.to_string());
        let mut w = csv::Writer::from_writer(Vec::new());
        w.write_record(self.columns.iter().map(|c| c.name.as_str()))
            .map_err(|e| failed(&e))?;
        for r in 0..self.rows() {
            let cells = self.columns.iter().map(|c| match &c.data {
                ColumnData::Int(v) => v[r].to_string(),
                ColumnData::Count(v) => v[r].map_or_else(String::new, |x| x.to_string()),
                ColumnData::Bool(v) => v[r].map_or_else(String::new, |x| x.to_string()),
                ColumnData::Float(v) => v[r].map_or_else(String::new, |x| format!("{x:?}")),
                ColumnData::Text(v) => v[r].clone().unwrap_or_default(),
            });
            w.write_record(cells).map_err(|e| failed(&e))?;
        }
        let bytes = w.into_inner().map_err(|e| failed(&e))?;
        String::from_utf8(bytes).map_err(|e| failed(&e))
    }

    /// Writes the table as Parquet to `path` (through a file beside it and
    /// a rename): `case` and counts INT64, numbers DOUBLE, flags BOOLEAN,
    /// text BYTE_ARRAY (UTF-8), every column but `case` optional; one row
    /// group, uncompressed.
    #[cfg(feature = "parquet")]
    pub fn write_parquet(&self, path: &std::path::Path) -> Result<(), StudyError> {
        let tmp = path.with_extension(format!("parquet.tmp.{}", std::process::id()));
        let file = std::fs::File::create(&tmp).map_err(|e| StudyError::io(&tmp, e))?;
        parquet_writer::write(self, file).map_err(|e| StudyError::io(path, e))?;
        std::fs::rename(&tmp, path).map_err(|e| StudyError::io(path, e))
    }

    /// The main effects of the numeric factors on `response` (a column
    /// index): for each factor, the mean response over the finished cases
    /// at each of its levels (levels grouped into 5 equal bins when there
    /// are more than 8, as in a Latin hypercube), the level scaled to 0
    /// (lowest) … 1 (highest). One trace per factor: (scaled level, mean).
    pub(crate) fn main_effects(&self, response: usize) -> Vec<(String, Vec<(f64, f64)>)> {
        let ColumnData::Float(y) = &self.columns[response].data else {
            return Vec::new();
        };
        let mut traces = Vec::new();
        for f in &self.columns[1..=self.factors] {
            let ColumnData::Float(x) = &f.data else {
                continue;
            };
            let pairs: Vec<(f64, f64)> = x
                .iter()
                .zip(y)
                .filter_map(|(x, y)| Some(((*x)?, (*y)?)))
                .filter(|(x, y)| x.is_finite() && y.is_finite())
                .collect();
            let (lo, hi) = pairs
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), (x, _)| {
                    (lo.min(*x), hi.max(*x))
                });
            if pairs.is_empty() {
                continue;
            }
            let span = if hi > lo { hi - lo } else { 1.0 };
            let mut levels: Vec<f64> = pairs.iter().map(|p| p.0).collect();
            levels.sort_by(f64::total_cmp);
            levels.dedup();
            let key = |x: f64| -> f64 {
                if levels.len() <= 8 {
                    (x - lo) / span
                } else {
                    // Bin centres of 5 equal bins.
                    let b = (((x - lo) / span) * 5.0).floor().min(4.0);
                    (b + 0.5) / 5.0
                }
            };
            let mut groups: Vec<(f64, f64, usize)> = Vec::new();
            for (x, y) in &pairs {
                let k = key(*x);
                match groups.iter_mut().find(|g| g.0 == k) {
                    Some(g) => {
                        g.1 += y;
                        g.2 += 1;
                    }
                    None => groups.push((k, *y, 1)),
                }
            }
            groups.sort_by(|a, b| a.0.total_cmp(&b.0));
            traces.push((
                format!("{} ({lo} … {hi})", f.name),
                groups
                    .into_iter()
                    .map(|(k, sum, n)| (k, sum / n as f64))
                    .collect(),
            ));
        }
        traces
    }

    /// Draws a main-effects figure per response into `dir`
    /// (`<response>.png` and `.svg`); returns how many were drawn. A
    /// response with no finished case is skipped.
    #[cfg(feature = "figures")]
    pub(crate) fn main_effects_figures(&self, dir: &std::path::Path) -> Result<usize, StudyError> {
        use crate::analysis::figures::{Mark, Plot, Trace, save};
        std::fs::create_dir_all(dir).map_err(|e| StudyError::io(dir, e))?;
        let mut drawn = 0;
        let first = 1 + self.factors;
        for r in first..first + self.responses {
            let name = &self.columns[r].name;
            let effects = self.main_effects(r);
            let plot = Plot {
                title: format!("Main effects on {name}"),
                x_label: "factor level, scaled: 0 = lowest, 1 = highest".to_owned(),
                y_label: format!("mean {name}"),
                traces: effects
                    .into_iter()
                    .enumerate()
                    .map(|(i, (label, points))| Trace {
                        label,
                        points,
                        mark: Mark::Line,
                        color: i,
                    })
                    .collect(),
                notes: Vec::new(),
            };
            if plot.traces.iter().all(|t| t.points.is_empty()) {
                continue;
            }
            match save(&plot, dir, name) {
                Ok(_) => drawn += 1,
                Err(crate::analysis::figures::FigureError::Empty(_)) => {}
                Err(e) => return Err(StudyError::io(dir, e)),
            }
        }
        Ok(drawn)
    }
}

/// The responses' names: every numeric field of the finished cases in
/// first-seen order, or the plan's list (each checked against them).
fn response_names(responses: &Responses, rows: &[CaseRow]) -> Result<Vec<String>, StudyError> {
    let mut available: Vec<String> = Vec::new();
    for f in rows.iter().filter_map(|r| r.fields.as_ref()) {
        for (name, _) in f {
            if !available.contains(name) {
                available.push(name.clone());
            }
        }
    }
    match responses {
        Responses::All => Ok(available),
        Responses::Fields(list) => {
            let any_ok = rows.iter().any(|r| r.fields.is_some());
            for (index, name) in list.iter().enumerate() {
                if any_ok && !available.contains(name) {
                    return Err(StudyError::UnknownResponse {
                        index,
                        name: name.clone(),
                        allowed: available.join(", "),
                    });
                }
            }
            Ok(list.clone())
        }
    }
}

/// A factor's column: numbers where every level is one, else text.
fn factor_column(name: &str, values: &[&toml::Value]) -> Column {
    let numbers: Option<Vec<Option<f64>>> = values
        .iter()
        .map(|v| match v {
            toml::Value::Float(x) => Some(Some(*x)),
            toml::Value::Integer(x) => Some(Some(*x as f64)),
            _ => None,
        })
        .collect();
    let data = match numbers {
        Some(x) => ColumnData::Float(x),
        None => ColumnData::Text(
            values
                .iter()
                .map(|v| Some(v.as_str().map_or_else(|| v.to_string(), str::to_owned)))
                .collect(),
        ),
    };
    Column {
        name: name.to_owned(),
        data,
    }
}

/// What the summaries say of their own numbers, named as in the summary:
/// `dt_auto`, each segment's `segments.<k>.stationary`, `warning_count`,
/// `warnings` (joined by [`WARNING_SEPARATOR`]; null without any), and the
/// case's `status` ([`RowStatus`]). Null for a case without a summary.
fn flag_columns(rows: &[CaseRow]) -> Vec<Column> {
    let segments = rows.iter().map(CaseRow::segments).max().unwrap_or(0);
    let mut columns = vec![Column {
        name: "dt_auto".to_owned(),
        data: ColumnData::Bool(
            rows.iter()
                .map(|r| r.summary.as_ref()?.get("dt_auto")?.as_bool())
                .collect(),
        ),
    }];
    for k in 0..segments {
        columns.push(Column {
            name: format!("segments.{k}.stationary"),
            data: ColumnData::Bool(rows.iter().map(|r| r.stationary(k)).collect()),
        });
    }
    let warnings: Vec<Option<Vec<String>>> = rows.iter().map(CaseRow::warnings).collect();
    columns.push(Column {
        name: "warning_count".to_owned(),
        data: ColumnData::Count(
            warnings
                .iter()
                .map(|w| w.as_ref().map(|w| w.len() as i64))
                .collect(),
        ),
    });
    columns.push(Column {
        name: "warnings".to_owned(),
        data: ColumnData::Text(
            warnings
                .iter()
                .map(|w| {
                    w.as_ref()
                        .filter(|w| !w.is_empty())
                        .map(|w| w.join(WARNING_SEPARATOR))
                })
                .collect(),
        ),
    });
    columns.push(Column {
        name: "status".to_owned(),
        data: ColumnData::Text(
            rows.iter()
                .map(|r| Some(r.row_status().name().to_owned()))
                .collect(),
        ),
    });
    columns
}

#[cfg(feature = "parquet")]
mod parquet_writer {
    use std::sync::Arc;

    use parquet::basic::{ConvertedType, LogicalType, Repetition, Type as Physical};
    use parquet::data_type::{BoolType, ByteArray, ByteArrayType, DoubleType, Int64Type};
    use parquet::errors::ParquetError;
    use parquet::file::properties::WriterProperties;
    use parquet::file::writer::SerializedFileWriter;
    use parquet::schema::types::Type;

    use super::{ColumnData, Table};

    /// The values present and the definition levels (1 present, 0 null).
    fn defined<T: Copy>(v: &[Option<T>]) -> (Vec<T>, Vec<i16>) {
        let def = v.iter().map(|x| i16::from(x.is_some())).collect();
        (v.iter().flatten().copied().collect(), def)
    }

    pub(super) fn write(table: &Table, file: std::fs::File) -> Result<(), ParquetError> {
        let mut fields = Vec::new();
        for c in &table.columns {
            let (physical, repetition) = match c.data {
                ColumnData::Int(_) => (Physical::INT64, Repetition::REQUIRED),
                ColumnData::Count(_) => (Physical::INT64, Repetition::OPTIONAL),
                ColumnData::Bool(_) => (Physical::BOOLEAN, Repetition::OPTIONAL),
                ColumnData::Float(_) => (Physical::DOUBLE, Repetition::OPTIONAL),
                ColumnData::Text(_) => (Physical::BYTE_ARRAY, Repetition::OPTIONAL),
            };
            let mut b = Type::primitive_type_builder(&c.name, physical).with_repetition(repetition);
            if let ColumnData::Text(_) = c.data {
                b = b
                    .with_logical_type(Some(LogicalType::String))
                    .with_converted_type(ConvertedType::UTF8);
            }
            fields.push(Arc::new(b.build()?));
        }
        let schema = Arc::new(
            Type::group_type_builder("results")
                .with_fields(fields)
                .build()?,
        );
        let props = Arc::new(WriterProperties::builder().build());
        let mut writer = SerializedFileWriter::new(file, schema, props)?;
        let mut group = writer.next_row_group()?;
        let mut columns = table.columns.iter();
        while let Some(mut out) = group.next_column()? {
            let Some(c) = columns.next() else {
                return Err(ParquetError::General("more columns than data".to_owned()));
            };
            match &c.data {
                ColumnData::Int(v) => {
                    out.typed::<Int64Type>().write_batch(v, None, None)?;
                }
                ColumnData::Count(v) => {
                    let (values, def) = defined(v);
                    out.typed::<Int64Type>()
                        .write_batch(&values, Some(&def), None)?;
                }
                ColumnData::Bool(v) => {
                    let (values, def) = defined(v);
                    out.typed::<BoolType>()
                        .write_batch(&values, Some(&def), None)?;
                }
                ColumnData::Float(v) => {
                    let (values, def) = defined(v);
                    out.typed::<DoubleType>()
                        .write_batch(&values, Some(&def), None)?;
                }
                ColumnData::Text(v) => {
                    let def: Vec<i16> = v.iter().map(|x| i16::from(x.is_some())).collect();
                    let values: Vec<ByteArray> = v
                        .iter()
                        .flatten()
                        .map(|s| ByteArray::from(s.as_str()))
                        .collect();
                    out.typed::<ByteArrayType>()
                        .write_batch(&values, Some(&def), None)?;
                }
            }
            out.close()?;
        }
        group.close()?;
        writer.close()?;
        Ok(())
    }
}
