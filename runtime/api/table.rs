//! Typed columns of a result table (a sweep's or a stability diagram's rows), what the Python
//! binding turns into numpy arrays and a DataFrame without a CSV in between.
//!
//! The typing rule is the one the Python package has always applied to the CSV's cells: a
//! column is integers if every cell is one, else floats if every cell is one or empty (an
//! empty cell is NaN), else text. Text is stored once per distinct value (`categories`) with a
//! code per row, so a million rows of `completed` cost four bytes each.

use std::collections::HashMap;

/// One typed column.
#[derive(Debug, Clone, PartialEq)]
pub enum Column {
    Int(Vec<i64>),
    Float(Vec<f64>),
    /// Row `i` holds `categories[codes[i]]`.
    Text { codes: Vec<u32>, categories: Vec<String> },
}

impl Column {
    pub fn len(&self) -> usize {
        match self {
            Column::Int(v) => v.len(),
            Column::Float(v) => v.len(),
            Column::Text { codes, .. } => codes.len(),
        }
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// A text column being filled, typed by [`TextBuilder::finish`].
#[derive(Debug, Clone, Default)]
pub struct TextBuilder {
    codes: Vec<u32>,
    categories: Vec<String>,
    index: HashMap<String, u32>,
}

impl TextBuilder {
    pub fn push(&mut self, cell: &str) {
        let code = match self.index.get(cell) {
            Some(&c) => c,
            None => {
                let c = self.categories.len() as u32;
                self.categories.push(cell.to_string());
                self.index.insert(cell.to_string(), c);
                c
            }
        };
        self.codes.push(code);
    }

    /// Integers if every cell is one (so also an empty column), else floats if every cell is
    /// one or empty (NaN), else text (the rule is applied to the distinct values, then spread
    /// over the rows).
    pub fn finish(self) -> Column {
        let TextBuilder { codes, categories, .. } = self;
        if let Some(ints) = categories.iter().map(|c| c.parse::<i64>().ok()).collect::<Option<Vec<_>>>() {
            return Column::Int(codes.iter().map(|&c| ints[c as usize]).collect());
        }
        let float = |c: &String| if c.is_empty() { Some(f64::NAN) } else { parse_float(c) };
        if let Some(floats) = categories.iter().map(float).collect::<Option<Vec<_>>>() {
            return Column::Float(codes.iter().map(|&c| floats[c as usize]).collect());
        }
        Column::Text { codes, categories }
    }
}

/// A float as Python's `float()` reads it (`NaN`, `inf`, `1e-6`, surrounding blanks).
fn parse_float(s: &str) -> Option<f64> {
    let t = s.trim();
    t.parse::<f64>().ok().or_else(|| match t.to_ascii_lowercase().as_str() {
        "nan" | "+nan" | "-nan" => Some(f64::NAN),
        "inf" | "+inf" | "infinity" | "+infinity" => Some(f64::INFINITY),
        "-inf" | "-infinity" => Some(f64::NEG_INFINITY),
        _ => None,
    })
}

/// A table: column names and typed columns of equal length.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Table {
    pub names: Vec<String>,
    pub columns: Vec<Column>,
}

impl Table {
    /// The table of rows of text fields (one per name), each column typed by the rule above.
    pub fn from_fields<'a>(names: Vec<String>, rows: impl IntoIterator<Item = &'a [String]>) -> Table {
        let mut builders: Vec<TextBuilder> = names.iter().map(|_| TextBuilder::default()).collect();
        for row in rows {
            for (b, cell) in builders.iter_mut().zip(row) {
                b.push(cell);
            }
        }
        Table { names, columns: builders.into_iter().map(TextBuilder::finish).collect() }
    }

    /// Number of rows.
    pub fn rows(&self) -> usize {
        self.columns.first().map_or(0, Column::len)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn col(cells: &[&str]) -> Column {
        let mut b = TextBuilder::default();
        cells.iter().for_each(|c| b.push(c));
        b.finish()
    }

    #[test]
    fn columns_are_typed_as_the_python_package_types_csv_cells() {
        assert_eq!(col(&["1", "2", "1"]), Column::Int(vec![1, 2, 1]));
        let Column::Float(f) = col(&["1", "2.5", ""]) else { panic!("not floats") };
        assert_eq!(&f[..2], &[1.0, 2.5]);
        assert!(f[2].is_nan());
        let Column::Float(f) = col(&["", ""]) else { panic!("an empty column is NaN") };
        assert!(f.iter().all(|x| x.is_nan()));
        assert!(matches!(col(&["NaN", "1e-6"]), Column::Float(_)));
        assert_eq!(
            col(&["completed", "", "completed", "blow_up"]),
            Column::Text { codes: vec![0, 1, 0, 2], categories: vec!["completed".into(), "".into(), "blow_up".into()] }
        );
        assert_eq!(col(&[]), Column::Int(vec![]));
    }
}
