//! Sparse `M = L^T L` factorisation of a joint-space matrix with the kinematic tree's sparsity
//! (Featherstone, *Rigid Body Dynamics Algorithms*, 2008, section 6.5, tables 6.3 and 6.4).
//!
//! Degrees of freedom are taken in tree order (`d`: the six base DOFs as a chain, then one per
//! body in body order), so every DOF's ancestors come first. Processing from the leaves, the
//! factor keeps exactly the tree's pattern: `L[i][j] != 0` only for `j` an ancestor of `i` (no
//! fill-in), so factoring costs O(nv d^2) and a solve O(nv d), `d` the depth, instead of
//! O(nv^3) and O(nv^2) for a dense Cholesky. `L^-T b` only touches the ancestors of `b`'s
//! non-zeros, which keeps `L^-T J^T` of a foot Jacobian on the leg and the base.
//! Vectors are in velocity-index order (the user's joint order); the map is internal.

use super::mul_add;
use crate::error::{Error, Result};
use crate::model::Model;
use nalgebra::{DMatrix, Vector6};

/// The base's six DOFs, the first six tree DOFs (a chain) and the last six entries of every
/// joint row.
const BASE_DOFS: usize = 6;

/// Widths up to which the multi-right-hand-side solves keep the pivot column on the stack.
const LOCAL_WIDTH: usize = 12;

/// The contact terms of one state computed with a factored `M + diag` (borrowed from whoever
/// computed them, e.g. the controller's torque map): what a second user of the same state,
/// model, diagonal and contact frames can take instead of computing them again.
#[derive(Clone, Copy, Debug)]
pub struct FactoredContacts<'a> {
    /// The contact frames, in row order (6 rows each).
    pub frames: &'a [crate::model::FrameId],
    /// The diagonal added to `M` before factoring (nv).
    pub diagonal: &'a [f64],
    /// `M + diag = L^T L`.
    pub factor: &'a TreeFactor,
    /// Stacked contact Jacobian `J` (k x nv), `[v_origin; omega]` world axes.
    pub jacobian: &'a DMatrix<f64>,
    /// `Jdot nu` of the contacts (k).
    pub jdot_nu: &'a nalgebra::DVector<f64>,
    /// `(L^-T J^T)^T` (k x nv), as [`TreeFactor::schur_complement`] leaves it.
    pub linv_jt_t: &'a DMatrix<f64>,
    /// `J (M + diag)^-1 J^T` (k x k), not factored.
    pub schur: &'a DMatrix<f64>,
}

/// The factor and the tree of DOFs.
///
/// Storage: row `d` of `L` holds only its structural non-zeros, the columns `d, parent(d),
/// parent(parent(d)), ..., 0` (the ancestor chain, `depth(d) + 1` entries), contiguously in
/// `values` from `row_start[d]`. The chain of an ancestor `i` of `d` is a suffix of `d`'s, so
/// the factor's update `L[i, chain(i)] -= L[k, i] L[k, chain(i)]` is a contiguous axpy.
#[derive(Clone, Debug)]
pub struct TreeFactor {
    /// Velocity index of tree DOF `d` (nv).
    velocity_index: Vec<usize>,
    /// Start of row `d` in `values` (nv + 1; row `d` ends at `row_start[d + 1]`).
    row_start: Vec<usize>,
    /// Tree DOF of each stored entry's column (as `values`).
    column_dof: Vec<usize>,
    /// Velocity index of each stored entry's column (as `values`).
    column_velocity: Vec<usize>,
    /// The entries of `L`, row by row along the ancestor chains; a row's first entry is its
    /// diagonal.
    values: Vec<f64>,
    /// Where each stored entry is read from in a column-major nv x nv matrix (as `values`).
    matrix_index: Vec<usize>,
    /// `1 / L[d, d]` per tree DOF (nv): the solves multiply by it, so no division sits on
    /// their dependency chains.
    inverse_pivot: Vec<f64>,
}

impl TreeFactor {
    /// An empty factor for `model`.
    pub fn new(model: &Model) -> Self {
        let mut velocity_index: Vec<usize> = (0..6).collect();
        let mut parent: Vec<Option<usize>> = (0..6usize).map(|d| d.checked_sub(1)).collect();
        for body in 1..model.n_bodies() {
            velocity_index.push(model.velocity_index(body));
            let p = model.parent(body);
            parent.push(Some(if p == 0 { 5 } else { 5 + p }));
        }
        let mut row_start = vec![0];
        let mut column_dof = Vec::new();
        for d in 0..parent.len() {
            let mut a = Some(d);
            while let Some(dof) = a {
                column_dof.push(dof);
                a = parent[dof];
            }
            row_start.push(column_dof.len());
        }
        let column_velocity: Vec<usize> = column_dof.iter().map(|&d| velocity_index[d]).collect();
        let nv = velocity_index.len();
        let mut matrix_index = Vec::with_capacity(column_dof.len());
        for (d, &vd) in velocity_index.iter().enumerate() {
            let row = &column_velocity[row_start[d]..row_start[d + 1]];
            matrix_index.extend(row.iter().map(|&column| vd + nv * column));
        }
        Self {
            values: vec![0.0; column_dof.len()],
            inverse_pivot: vec![0.0; nv],
            matrix_index,
            velocity_index,
            row_start,
            column_dof,
            column_velocity,
        }
    }

    /// Copies the factor of `other`, a factor of the same model (no allocation).
    pub fn copy_values_from(&mut self, other: &TreeFactor) {
        self.values.copy_from_slice(&other.values);
        self.inverse_pivot.copy_from_slice(&other.inverse_pivot);
    }

    /// Factors `matrix + diag(diagonal)` (both in velocity indices; `diagonal` may be empty).
    /// The matrix must have the tree's sparsity (a joint-space inertia does). Fails if a pivot
    /// is not positive.
    pub fn factor(&mut self, matrix: &DMatrix<f64>, diagonal: &[f64]) -> Result<()> {
        let n = self.velocity_index.len();
        assert_eq!(matrix.shape(), (n, n), "tree factor: matrix shape");
        let m = matrix.as_slice();
        for (value, &index) in self.values.iter_mut().zip(&self.matrix_index) {
            *value = m[index];
        }
        if !diagonal.is_empty() {
            for d in 0..n {
                self.values[self.row_start[d]] += diagonal[self.velocity_index[d]];
            }
        }
        // From the leaves: ancestors have smaller tree indices, so their rows lie before row k.
        // Joint rows first; their updates of the base block (the last six entries of every
        // joint row are the base DOFs 5..0) are summed as dense 6 x 6 rank-one updates, one
        // fixed-size operation per row instead of six short loops.
        let mut base_update = [0.0; 36];
        for k in (BASE_DOFS..n).rev() {
            let u = self.eliminate_row(k, BASE_DOFS)?;
            add_outer_product(&mut base_update, u.as_slice(), u.as_slice());
        }
        for i in 0..BASE_DOFS {
            let start = self.row_start[i];
            for t in 0..=i {
                // Entry (5 - i, 5 - i + t) of the column-major 6 x 6 sum.
                self.values[start + t] -= base_update[(5 - i + t) * 6 + 5 - i];
            }
        }
        for k in (0..BASE_DOFS).rev() {
            self.eliminate_row(k, 0)?;
        }
        Ok(())
    }

    /// Step `k` of the factorisation: the pivot and row `k` of `L`, and the updates of the rows
    /// of its ancestors except the last `skip_last` entries of row `k` (the base DOFs of a
    /// joint row, which the caller updates; 0 for a base row). Returns those last entries of
    /// row `k` (the base entries `L[k, 5..0]` for a joint row; unused for a base row).
    #[inline(always)]
    fn eliminate_row(&mut self, k: usize, skip_last: usize) -> Result<Vector6<f64>> {
        let (start, end) = (self.row_start[k], self.row_start[k + 1]);
        let (head, tail) = self.values.split_at_mut(start);
        let row_k = &mut tail[..end - start];
        let pivot = row_k[0];
        if pivot <= 0.0 || !pivot.is_finite() {
            return Err(Error::numerical(
                "tree Cholesky factorisation",
                format!(
                    "matrix is not positive definite (tree pivot {k}, velocity index {})",
                    self.velocity_index[k]
                ),
            ));
        }
        let lkk = pivot.sqrt();
        row_k[0] = lkk;
        let inverse = 1.0 / lkk;
        self.inverse_pivot[k] = inverse;
        row_k[1..].iter_mut().for_each(|v| *v *= inverse);
        let updated = row_k.len() - skip_last;
        for p in 1..updated {
            let i = self.column_dof[start + p];
            let lki = row_k[p];
            let row_i = &mut head[self.row_start[i]..self.row_start[i + 1]];
            for (target, source) in row_i.iter_mut().zip(&row_k[p..]) {
                *target = mul_add(-lki, *source, *target);
            }
        }
        Ok(if skip_last == BASE_DOFS {
            Vector6::from_column_slice(&row_k[updated..])
        } else {
            Vector6::zeros()
        })
    }

    /// `b <- L^-T b` (b in velocity indices, size nv).
    ///
    /// Every joint row ends with the base DOFs, so all of them update the same six entries of
    /// `b`: summed in a register-held 6-vector and applied once, instead of 6 x (joint rows)
    /// read-modify-writes of memory in one dependency chain.
    pub fn solve_lt(&self, b: &mut [f64]) {
        let n = self.velocity_index.len();
        let mut base_update = [0.0; BASE_DOFS];
        for i in (BASE_DOFS..n).rev() {
            let (start, end) = (self.row_start[i], self.row_start[i + 1]);
            let yi = b[self.velocity_index[i]] * self.inverse_pivot[i];
            b[self.velocity_index[i]] = yi;
            if yi == 0.0 {
                continue;
            }
            let base_start = end - BASE_DOFS;
            for (value, &column) in self.values[start + 1..base_start]
                .iter()
                .zip(&self.column_velocity[start + 1..base_start])
            {
                b[column] = mul_add(-value, yi, b[column]);
            }
            for (update, value) in base_update.iter_mut().zip(&self.values[base_start..end]) {
                *update = mul_add(*value, yi, *update);
            }
        }
        // Entry t of a joint row's base part is base DOF 5 - t.
        for (t, update) in base_update.iter().enumerate() {
            b[self.velocity_index[BASE_DOFS - 1 - t]] -= update;
        }
        for i in (0..BASE_DOFS).rev() {
            let (start, end) = (self.row_start[i], self.row_start[i + 1]);
            let yi = b[self.velocity_index[i]] * self.inverse_pivot[i];
            b[self.velocity_index[i]] = yi;
            for (value, &column) in self.values[start + 1..end]
                .iter()
                .zip(&self.column_velocity[start + 1..end])
            {
                b[column] = mul_add(-value, yi, b[column]);
            }
        }
    }

    /// `b <- L^-1 b` (b in velocity indices, size nv).
    ///
    /// A joint row's product with the base part of `b` (known once the base rows are solved) is
    /// a fixed-size dot product off the chain of dependent rows.
    pub fn solve_l(&self, b: &mut [f64]) {
        let n = self.velocity_index.len();
        for i in 0..BASE_DOFS.min(n) {
            let (start, end) = (self.row_start[i], self.row_start[i + 1]);
            let dot: f64 = self.values[start + 1..end]
                .iter()
                .zip(&self.column_velocity[start + 1..end])
                .fold(0.0, |sum, (value, &column)| mul_add(*value, b[column], sum));
            let vi = self.velocity_index[i];
            b[vi] = (b[vi] - dot) * self.inverse_pivot[i];
        }
        // The base part of `b` in a joint row's storage order (base DOFs 5..0).
        let base: [f64; BASE_DOFS] =
            std::array::from_fn(|t| b[self.velocity_index[BASE_DOFS - 1 - t]]);
        for i in BASE_DOFS..n {
            let (start, end) = (self.row_start[i], self.row_start[i + 1]);
            let base_start = end - BASE_DOFS;
            let chain = self.values[start + 1..base_start]
                .iter()
                .zip(&self.column_velocity[start + 1..base_start])
                .fold(0.0, |sum, (value, &column)| mul_add(*value, b[column], sum));
            // The base part apart (its inputs are known since the base rows), so that only the
            // chain's own sum waits for the rows solved just before.
            let base_dot = self.values[base_start..end]
                .iter()
                .zip(&base)
                .fold(0.0, |sum, (value, b)| mul_add(*value, *b, sum));
            let dot = chain + base_dot;
            let vi = self.velocity_index[i];
            b[vi] = (b[vi] - dot) * self.inverse_pivot[i];
        }
    }

    /// `b <- (L^T L)^-1 b`.
    pub fn solve(&self, b: &mut [f64]) {
        self.solve_lt(b);
        self.solve_l(b);
    }

    /// `B <- L^-T B` for `k` right-hand sides at once, given transposed: `b_t = B^T` (k x nv), so
    /// the k entries of one velocity index are a contiguous column and every entry of the factor
    /// is used once, in an axpy over all right-hand sides (instead of k passes over the factor).
    /// A velocity index whose k entries are all zero is skipped: `L^-T` only moves entries to
    /// ancestors, so a foot Jacobian's rows cost its leg and the base, not the whole tree.
    pub fn solve_lt_multi(&self, b_t: &mut DMatrix<f64>) {
        let k = b_t.nrows();
        with_fixed_width!(k, |width| self
            .solve_lt_multi_kernel(b_t.as_mut_slice(), width));
    }

    #[inline(always)]
    fn solve_lt_multi_kernel(&self, b: &mut [f64], k: usize) {
        for i in (0..self.velocity_index.len()).rev() {
            let (start, end) = (self.row_start[i], self.row_start[i + 1]);
            let vi = self.velocity_index[i];
            let yi = &mut b[vi * k..vi * k + k];
            if yi.iter().all(|&v| v == 0.0) {
                continue;
            }
            let inverse = self.inverse_pivot[i];
            yi.iter_mut().for_each(|v| *v *= inverse);
            if k <= LOCAL_WIDTH {
                // A copy on the stack: the updates below then borrow only their target.
                let mut local = [0.0; LOCAL_WIDTH];
                local[..k].copy_from_slice(yi);
                let source = &local[..k];
                for (&value, &column) in self.values[start + 1..end]
                    .iter()
                    .zip(&self.column_velocity[start + 1..end])
                {
                    let target = &mut b[column * k..column * k + k];
                    for (t, s) in target.iter_mut().zip(source) {
                        *t = mul_add(-value, *s, *t);
                    }
                }
                continue;
            }
            for (&value, &column) in self.values[start + 1..end]
                .iter()
                .zip(&self.column_velocity[start + 1..end])
            {
                let (source, target) = column_pair(b, k, vi, column);
                for (t, s) in target.iter_mut().zip(source) {
                    *t = mul_add(-value, *s, *t);
                }
            }
        }
    }

    /// `B <- L^-1 B` for `k` right-hand sides given transposed, `b_t = B^T` (k x nv), as in
    /// [`Self::solve_lt_multi`] (from the root: each velocity index gathers its ancestors).
    pub fn solve_l_multi(&self, b_t: &mut DMatrix<f64>) {
        let k = b_t.nrows();
        with_fixed_width!(k, |width| self
            .solve_l_multi_kernel(b_t.as_mut_slice(), width));
    }

    #[inline(always)]
    fn solve_l_multi_kernel(&self, b: &mut [f64], k: usize) {
        for i in 0..self.velocity_index.len() {
            let (start, end) = (self.row_start[i], self.row_start[i + 1]);
            let vi = self.velocity_index[i];
            let inverse = self.inverse_pivot[i];
            if k <= LOCAL_WIDTH {
                // Accumulated on the stack: the ancestors are then only read.
                let mut local = [0.0; LOCAL_WIDTH];
                let target = &mut local[..k];
                target.copy_from_slice(&b[vi * k..vi * k + k]);
                for (&value, &column) in self.values[start + 1..end]
                    .iter()
                    .zip(&self.column_velocity[start + 1..end])
                {
                    let source = &b[column * k..column * k + k];
                    for (t, s) in target.iter_mut().zip(source) {
                        *t = mul_add(-value, *s, *t);
                    }
                }
                for (out, t) in b[vi * k..vi * k + k].iter_mut().zip(target.iter()) {
                    *out = t * inverse;
                }
                continue;
            }
            for (&value, &column) in self.values[start + 1..end]
                .iter()
                .zip(&self.column_velocity[start + 1..end])
            {
                let (source, target) = column_pair(b, k, column, vi);
                for (t, s) in target.iter_mut().zip(source) {
                    *t = mul_add(-value, *s, *t);
                }
            }
            b[vi * k..vi * k + k].iter_mut().for_each(|v| *v *= inverse);
        }
    }

    /// `y_t = (L^-T J^T)^T` (k x nv) and `schur = J (L^T L)^-1 J^T = y_t y_t^T` (k x k) for `J`
    /// (k x nv). The Schur complement is summed velocity index by velocity index as outer
    /// products of `y_t`'s columns, each restricted to its non-zero rows, so branches without
    /// contacts cost nothing.
    pub fn schur_complement(
        &self,
        jacobian: &DMatrix<f64>,
        y_t: &mut DMatrix<f64>,
        schur: &mut DMatrix<f64>,
    ) {
        let k = jacobian.nrows();
        crate::dense::copy_contiguous(y_t, jacobian);
        self.solve_lt_multi(y_t);
        let (y, s) = (y_t.as_slice(), schur.as_mut_slice());
        match k {
            // The contact sizes: stack accumulators, every entry of `s` overwritten.
            6 => sum_outer_products_one_contact(y, s),
            12 => sum_outer_products_two_contacts(y, s),
            _ => {
                // A slice fill: nalgebra's `fill` steps through its strides entry by entry.
                s.fill(0.0);
                sum_outer_products(y, s, k)
            }
        }
    }
}

/// `s = sum_i y_i y_i^T` over the k-entry columns `y_i` of `y` (k x nv), each restricted to
/// its non-zero rows (a leg's index only carries its own foot's rows, other branches none);
/// `s` (k x k, zero on entry) gets the lower triangle summed, then mirrored.
#[inline(always)]
fn sum_outer_products(y: &[f64], s: &mut [f64], k: usize) {
    for column in y.chunks_exact(k) {
        let Some(first) = column.iter().position(|&v| v != 0.0) else {
            continue;
        };
        let last = column.iter().rposition(|&v| v != 0.0).unwrap_or(first);
        // Lower triangle of column c: rows c..=last.
        for c in first..=last {
            let yc = column[c];
            let target = &mut s[c * k + c..c * k + last + 1];
            for (t, y) in target.iter_mut().zip(&column[c..=last]) {
                *t = mul_add(*y, yc, *t);
            }
        }
    }
    for c in 0..k {
        for r in c + 1..k {
            s[r * k + c] = s[c * k + r];
        }
    }
}

/// [`sum_outer_products`] for one contact (k = 6): full 6 x 6 rank-one updates of a stack
/// array, skipping zero columns (fixed-length, unrolled loops beat the triangle's short ones).
fn sum_outer_products_one_contact(y: &[f64], s: &mut [f64]) {
    let mut sum = [0.0; 36];
    for column in y.chunks_exact(6) {
        if column.iter().any(|&v| v != 0.0) {
            add_outer_product(&mut sum, column, column);
        }
    }
    s.copy_from_slice(&sum);
}

/// `sum += rows columns^T` for a column-major 6 x 6 `sum` (plain arrays: fixed-length loops
/// the compiler unrolls and vectorises).
#[inline(always)]
fn add_outer_product(sum: &mut [f64; 36], rows: &[f64], columns: &[f64]) {
    for (target, &c) in sum.chunks_exact_mut(6).zip(columns) {
        for (t, &r) in target.iter_mut().zip(rows) {
            *t = mul_add(r, c, *t);
        }
    }
}

/// [`sum_outer_products`] for two contacts (k = 12) in 6 x 6 blocks: a velocity index on one
/// foot's leg carries only that foot's six rows, so it updates one diagonal block (36
/// products) instead of the whole matrix (144); only the shared indices (the base) update all
/// three blocks.
fn sum_outer_products_two_contacts(y: &[f64], s: &mut [f64]) {
    let (mut first, mut second, mut cross) = ([0.0; 36], [0.0; 36], [0.0; 36]);
    for column in y.chunks_exact(12) {
        let (a, b) = column.split_at(6);
        let (has_a, has_b) = (a.iter().any(|&v| v != 0.0), b.iter().any(|&v| v != 0.0));
        if has_a {
            add_outer_product(&mut first, a, a);
        }
        if has_b {
            add_outer_product(&mut second, b, b);
        }
        if has_a && has_b {
            add_outer_product(&mut cross, b, a);
        }
    }
    // Column-major 12 x 12: [first, cross^T; cross, second].
    for c in 0..6 {
        for r in 0..6 {
            s[c * 12 + r] = first[c * 6 + r];
            s[c * 12 + 6 + r] = cross[c * 6 + r];
            s[(6 + c) * 12 + r] = cross[r * 6 + c];
            s[(6 + c) * 12 + 6 + r] = second[c * 6 + r];
        }
    }
}

/// The k-entry columns `source` and `target` (distinct) of a k x nv column-major slice.
#[inline]
fn column_pair(b: &mut [f64], k: usize, source: usize, target: usize) -> (&[f64], &mut [f64]) {
    debug_assert_ne!(source, target);
    if source < target {
        let (head, tail) = b.split_at_mut(target * k);
        (&head[source * k..source * k + k], &mut tail[..k])
    } else {
        let (head, tail) = b.split_at_mut(source * k);
        (&tail[..k], &mut head[target * k..target * k + k])
    }
}
