//! POV-Ray's arrays: `array[N]` and `array[N][M]…`, with or without a
//! `{ … }` initializer, elements declared by `#declare A[i] = …` and read
//! as `A[i]` wherever a declared name of their kind may stand (a number in
//! an expression, an object in `object { A[i] }`, a texture, …), and
//! `dimensions` and `dimension_size`.
//!
//! As in POV-Ray 3.7 (checked against its `#debug` output): an index is
//! truncated to an integer, `#declare B = A` copies the array, and an
//! array passed to a macro is the caller's own, so the macro's
//! `#declare Arr[i] = …` changes it. Reading an element never declared is
//! an error, as is an initializer with too few or too many elements.

use std::cell::RefCell;
use std::rc::Rc;

use super::lex::{Tok, Token};
use super::parse::{Frame, Loc, Parser};
use super::value::Value;
use crate::error::Result;

/// The most elements one array may have: a hostile `array[1e12]` is an
/// error at its size, not an allocation that takes the machine's memory.
const MAX_ITEMS: usize = 1 << 22;

/// An array's sizes and its elements, row by row (None: not declared yet).
#[derive(Clone, Debug)]
pub struct Array {
    dims: Vec<usize>,
    items: Vec<Option<Value>>,
}

/// The elements all arrays of one scene may make or copy in all
/// (16,777,216): a loop that makes or copies a large array on every pass
/// stops with an error instead of running for hours (a million passes of
/// a 4-million-element array). Far above what a scene builds:
/// benchmark.pov's lathe mesh makes about 40,000.
const MAX_ARRAY_WORK: usize = 1 << 24;

/// An array as a value: shared, so that a macro's parameter is the
/// caller's array (see [`Parser::copied`], which a declaration applies).
pub type SharedArray = Rc<RefCell<Array>>;

impl Parser {
    /// A separate copy of `value` if it is an array, for a declaration:
    /// POV-Ray copies an array that `#declare B = A` names.
    pub(super) fn copied(&mut self, value: Value, loc: Loc) -> Result<Value> {
        Ok(match value {
            Value::Array(a) => {
                self.array_work(a.borrow().items.len(), loc)?;
                let copy = a.borrow().clone();
                Value::Array(Rc::new(RefCell::new(copy)))
            }
            other => other,
        })
    }

    /// Counts `items` more elements made or copied, against
    /// [`MAX_ARRAY_WORK`].
    fn array_work(&mut self, items: usize, loc: Loc) -> Result<()> {
        self.array_items += items;
        if self.array_items > MAX_ARRAY_WORK {
            return Err(self.error_at(
                loc,
                format!(
                    "arrays have made or copied {MAX_ARRAY_WORK} elements in all: \
                     does a loop make or copy a large array on every pass?"
                ),
            ));
        }
        Ok(())
    }

    /// An array after its keyword `array`: its sizes, then an initializer
    /// if one follows.
    pub(super) fn array_value(&mut self, loc: Loc) -> Result<Value> {
        let mut dims = Vec::new();
        // The `[` of a size and the `{` of an initializer are looked for
        // as they stand: a directive after the declaration may use its name
        // (`#declare A = array[4]` then `#declare A[0] = …`), so looking
        // ahead must not run it.
        while self.raw_is('[') {
            self.advance();
            let at = self.here();
            let n = self.float()?;
            self.expect(']')?;
            if !(n >= 1.0 && n < (MAX_ITEMS + 1) as f64) {
                return Err(self.error_at(
                    at,
                    format!("an array's size must be 1 to {MAX_ITEMS}, not {n}"),
                ));
            }
            dims.push(n as usize);
        }
        let total = dims
            .iter()
            .try_fold(1usize, |t, &n| t.checked_mul(n).filter(|&t| t <= MAX_ITEMS));
        let Some(total) = total.filter(|_| !dims.is_empty()) else {
            return Err(self.error_at(
                loc,
                format!(
                    "an array needs a size, `array[N]`, and at most {MAX_ITEMS} elements in all"
                ),
            ));
        };
        self.array_work(total, loc)?;
        let mut items = Vec::with_capacity(total);
        if self.raw_is('{') {
            self.advance();
            self.initializer(&dims, &mut items)?;
        } else {
            items.resize(total, None);
        }
        Ok(Value::Array(Rc::new(RefCell::new(Array { dims, items }))))
    }

    /// The elements of an initializer for sizes `dims`, after its `{`, up
    /// to and with its `}`: `{ a, b, c }`, or for more than one size a
    /// list of such lists. Commas between them, and after the last, are
    /// optional, as in POV-Ray.
    fn initializer(&mut self, dims: &[usize], items: &mut Vec<Option<Value>>) -> Result<()> {
        let loc = self.last();
        let mut count = 0;
        while !self.eat('}')? {
            if count == dims[0] {
                return Err(self.error_at(
                    loc,
                    format!(
                        "this array's initializer has more than {} elements",
                        dims[0]
                    ),
                ));
            }
            if dims.len() > 1 {
                self.expect('{')?;
                self.nested(|p| p.initializer(&dims[1..], items))?;
            } else {
                items.push(Some(self.value()?));
            }
            count += 1;
            // The commas between elements are optional, as in POV-Ray
            // (allpatterns.pov's list of names has none at its line ends).
            self.eat(',')?;
        }
        if count < dims[0] {
            return Err(self.error_at(
                loc,
                format!(
                    "this array's initializer has {count} elements, its size {}",
                    dims[0]
                ),
            ));
        }
        Ok(())
    }

    /// The index into `array` (declared as `name`) of the `[i][j]…` ahead,
    /// and the element's name with its indices (`A[2][0]`).
    fn index(&mut self, name: &str, array: &SharedArray) -> Result<(usize, String)> {
        let dims = array.borrow().dims.clone();
        let (mut flat, mut shown) = (0, name.to_owned());
        for (k, &n) in dims.iter().enumerate() {
            if !self.eat('[')? {
                return Err(self.error(format!(
                    "`{name}` has {} dimensions: expected `[` for dimension {}",
                    dims.len(),
                    k + 1
                )));
            }
            let at = self.here();
            let i = self.float()?.trunc();
            self.expect(']')?;
            if !(i >= 0.0 && i < n as f64) {
                return Err(self.error_at(
                    at,
                    format!(
                        "index {i} is outside `{name}`, whose dimension {} has size {n}",
                        k + 1
                    ),
                ));
            }
            flat = flat * n + i as usize;
            shown.push_str(&format!("[{i}]"));
        }
        Ok((flat, shown))
    }

    /// The element of `name` whose indices come next, and its name.
    pub(super) fn element(
        &mut self,
        name: &str,
        array: &SharedArray,
        loc: Loc,
    ) -> Result<(Value, String)> {
        let (flat, shown) = self.index(name, array)?;
        let item = array.borrow().items[flat].clone();
        match item {
            Some(value) => Ok((value, shown)),
            None => Err(self.error_at(loc, format!("`{shown}` was never declared"))),
        }
    }

    /// Whether the word at the top of the stream is an array with an index
    /// after it (see `substitute_element`).
    pub(super) fn indexes_array(&self, name: &str) -> bool {
        matches!(self.symbol(name), Some(Value::Array(_)))
            && self.raw_after() == Some(&Tok::Punct('['))
    }

    /// After the word `name` of an array is taken, reads the index after it
    /// and puts the element's name (`A[2]`, declared as the element) in the
    /// word's place: so wherever a declared value may stand, an element may
    /// too (`object { Deco[3] rotate y*90 }`).
    pub(super) fn substitute_element(&mut self, name: &str, loc: Loc) -> Result<()> {
        let Some(Value::Array(array)) = self.symbol(name).cloned() else {
            return Err(self.error_at(loc, format!("`{name}` is not an array")));
        };
        let (value, shown) = self.element(name, &array, loc)?;
        // The element stands under a name of its own, so the warnings its
        // array's declaration met are given here: all of them, as an
        // element's own are not kept apart. (Its counts for `info` are not:
        // they would count the whole array at each element.)
        self.warnings_of(name);
        self.set(&shown, value);
        self.push_frame(Frame {
            file: loc.file,
            tokens: Rc::new(vec![Token {
                tok: Tok::Word(shown),
                at: loc.at,
            }]),
            pos: 0,
            end: 1,
            blocks: Vec::new(),
            locals: Vec::new(),
            refs: Vec::new(),
        })
    }

    /// `#declare NAME[i]… = value`, after the name: declares the element.
    pub(super) fn declare_element(&mut self, name: &str, loc: Loc) -> Result<()> {
        let Some(Value::Array(array)) = self.symbol(name).cloned() else {
            return Err(self.error_at(
                loc,
                format!("`{name}` is not an array (declare it `#declare {name} = array[N]`)"),
            ));
        };
        let (flat, _) = self.index(name, &array)?;
        self.expect('=')?;
        let value = self.value()?;
        let value = self.copied(value, loc)?;
        array.borrow_mut().items[flat] = Some(value);
        self.eat(';')?;
        Ok(())
    }

    /// `dimensions(A)` or `dimension_size(A, k)`, after the function's name.
    pub(super) fn array_function(&mut self, function: &str, loc: Loc) -> Result<Value> {
        self.expect('(')?;
        let name = self.word()?;
        let Some(Value::Array(array)) = self.symbol(&name).cloned() else {
            return Err(self.error_at(
                loc,
                format!("`{function}` takes an array, and `{name}` is not one"),
            ));
        };
        let dims = array.borrow().dims.clone();
        let value = if function == "dimensions" {
            dims.len() as f64
        } else {
            self.expect(',')?;
            let k = self.float()?.trunc();
            if !(k >= 1.0 && k <= dims.len() as f64) {
                return Err(self.error_at(
                    loc,
                    format!("`{name}` has {} dimensions, not {k}", dims.len()),
                ));
            }
            dims[k as usize - 1] as f64
        };
        self.expect(')')?;
        Ok(Value::Float(value))
    }
}
