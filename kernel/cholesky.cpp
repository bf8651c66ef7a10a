#include "cholesky.hpp"

#include <amd.h>
#include <cholmod.h>

#include <algorithm>
#include <cmath>
#include <utility>
#include <limits>
#include <mutex>
#include <stdexcept>
#include <string>

#ifdef PYFRUSTRATE_HAVE_OPENMP
#include <omp.h>
#endif

namespace pyfrustrate {
namespace {

cholmod_common* common_of(void* p) { return static_cast<cholmod_common*>(p); }

// Debian's CHOLMOD runs parts of its supernodal factorisation in OpenMP teams of a fixed four
// threads (CHOLMOD_OMP_NUM_THREADS, a compile-time constant that omp_set_num_threads cannot
// override). On these matrices the teams cost more than they give: measured at R = 10 / 25 on
// 2 cores, 6-25 ms / 80-165 ms per factorisation with them, 1.2-2 ms / 37-50 ms without. The
// kernel is single-threaded by design (parallelism comes from independent jobs), so each CHOLMOD
// call runs with parallel regions made inactive (max-active-levels 0), restored afterwards.
class SerialOpenMP {
   public:
#ifdef PYFRUSTRATE_HAVE_OPENMP
    SerialOpenMP() : saved_(omp_get_max_active_levels()) { omp_set_max_active_levels(0); }
    ~SerialOpenMP() { omp_set_max_active_levels(saved_); }

   private:
    int saved_;
#endif
};

// CHOLMOD's numeric factorisation and solve call the BLAS on their dense supernodes. Debian's
// single-threaded OpenBLAS (libopenblas0-serial) is not safe to call from two threads at once:
// two replicas of pf.replica_exchange relaxing side by side got factorisations that differed in
// the last digits from run to run (energy traces 1e-9 apart after 300 rounds, then different
// Metropolis decisions), and reproducible ones with the reference BLAS preloaded. These calls
// therefore hold one process-wide lock (uncontended in a single-threaded run); the symbolic
// analysis, the kernel's own LDL^T and everything else still run in parallel.
std::mutex& blas_lock() {
    static std::mutex m;
    return m;
}

// A right-hand side as CHOLMOD's dense column, viewing b's storage (cholmod_solve only reads it),
// and a solution CHOLMOD allocated, copied out and freed.
cholmod_dense dense_view(const Eigen::VectorXd& b) {
    cholmod_dense rhs;
    rhs.nrow = b.size();
    rhs.ncol = 1;
    rhs.nzmax = b.size();
    rhs.d = b.size();
    rhs.x = const_cast<double*>(b.data());
    rhs.z = nullptr;
    rhs.xtype = CHOLMOD_REAL;
    rhs.dtype = CHOLMOD_DOUBLE;
    return rhs;
}

Eigen::VectorXd take_dense(cholmod_dense* x, cholmod_common* c) {
    Eigen::VectorXd out = Eigen::Map<const Eigen::VectorXd>(static_cast<double*>(x->x), x->nrow);
    cholmod_free_dense(&x, c);
    return out;
}

// x <- (L D L^T)^-1 x for a unit lower triangular L stored by columns: the below-diagonal
// entries of column j at row[k], value[k] for k in [begin(j), end(j)), D's entries diagonal(j).
// x[j] is held in a local in each column's loop (the compiler cannot prove that no row[k] is j);
// the operations and their order are those of the plain loops, so is the result.
template <class Begin, class End, class Diagonal>
void ldl_solve_in_place(int n, Begin begin, End end, const int* row, const double* value, Diagonal diagonal,
                        Eigen::VectorXd& solution) {
    double* x = solution.data();
    for (int j = 0; j < n; ++j) {
        const double xj = x[j];
        for (int k = begin(j), last = end(j); k < last; ++k) x[row[k]] -= value[k] * xj;
    }
    for (int j = 0; j < n; ++j) x[j] /= diagonal(j);
    for (int j = n - 1; j >= 0; --j) {
        double xj = x[j];
        for (int k = begin(j), last = end(j); k < last; ++k) xj -= value[k] * x[row[k]];
        x[j] = xj;
    }
}

}  // namespace

namespace {

// CHOLMOD's rule for its supernodal factorisation (Common->supernodal_switch, default 40): flops
// per entry of L at or above it.
constexpr double kSupernodalSwitch = 40.0;

// AMD's fill-reducing ordering of the quotient graph whose nodes are the groups node_of gives
// the degrees of freedom (a network's corners: both coordinates of a corner touch the same
// entries), expanded to the degrees of freedom, those of a node consecutive in increasing order.
// The graph has a quarter of the entries of the matrix's, and AMD's work falls with it; the fill
// is the same up to ties, since AMD merges indistinguishable nodes anyway. Empty if AMD fails.
std::vector<int> quotient_amd_ordering(int n, const std::vector<int>& column_start, const std::vector<int>& row,
                                       const std::vector<int>& node_of) {
    const int m = n ? *std::max_element(node_of.begin(), node_of.end()) + 1 : 0;
    // Edges between distinct nodes, both ways, bucketed by their second node and then, stably, by
    // their first: each node's neighbours come out sorted (two counting sorts), then deduplicated.
    std::vector<int> second_start(m + 1, 0), first_start(m + 1, 0);
    for (int j = 0; j < n; ++j)
        for (int p = column_start[j]; p < column_start[j + 1]; ++p) {
            const int a = node_of[row[p]], b = node_of[j];
            if (a == b) continue;
            ++second_start[a + 1], ++second_start[b + 1];
            ++first_start[a + 1], ++first_start[b + 1];
        }
    for (int k = 0; k < m; ++k) second_start[k + 1] += second_start[k], first_start[k + 1] += first_start[k];
    std::vector<int> by_second(second_start[m]);  // the first node of each edge, bucketed by the second
    {
        std::vector<int> next(second_start.begin(), second_start.end() - 1);
        for (int j = 0; j < n; ++j)
            for (int p = column_start[j]; p < column_start[j + 1]; ++p) {
                const int a = node_of[row[p]], b = node_of[j];
                if (a == b) continue;
                by_second[next[b]++] = a;
                by_second[next[a]++] = b;
            }
    }
    std::vector<int> ai(first_start[m]);
    {
        std::vector<int> next(first_start.begin(), first_start.end() - 1);
        for (int b = 0; b < m; ++b)
            for (int q = second_start[b]; q < second_start[b + 1]; ++q) ai[next[by_second[q]]++] = b;
    }
    std::vector<int> ap(m + 1, 0);
    int kept = 0;
    for (int a = 0; a < m; ++a) {
        const int begin = kept;
        for (int q = first_start[a]; q < first_start[a + 1]; ++q)
            if (kept == begin || ai[kept - 1] != ai[q]) ai[kept++] = ai[q];
        ap[a + 1] = kept;
    }
    std::vector<int> node_order(m);
    double control[AMD_CONTROL], info[AMD_INFO];
    amd_defaults(control);
    if (amd_order(m, ap.data(), ai.data(), node_order.data(), control, info) != AMD_OK) return {};
    // The nodes' degrees of freedom (a counting sort by node, increasing within each).
    std::vector<int> dof_start(m + 1, 0), dofs(n);
    for (int j = 0; j < n; ++j) ++dof_start[node_of[j] + 1];
    for (int k = 0; k < m; ++k) dof_start[k + 1] += dof_start[k];
    {
        std::vector<int> next(dof_start.begin(), dof_start.end() - 1);
        for (int j = 0; j < n; ++j) dofs[next[node_of[j]]++] = j;
    }
    std::vector<int> perm;
    perm.reserve(n);
    for (const int k : node_order) perm.insert(perm.end(), dofs.begin() + dof_start[k], dofs.begin() + dof_start[k + 1]);
    return perm;
}

}  // namespace

CholeskyAnalysis::CholeskyAnalysis(int n, const std::vector<int>& column_start, const std::vector<int>& row,
                                   bool own_ldl, const std::vector<int>* node_of)
    : n_(n), nnz_(row.size()) {
    if (n < 1) throw std::invalid_argument("sparse Cholesky: empty matrix");
    if (static_cast<int>(column_start.size()) != n + 1 || column_start.front() != 0 ||
        column_start.back() != static_cast<int>(row.size()) ||
        !std::is_sorted(column_start.begin(), column_start.end()))
        throw std::invalid_argument("sparse Cholesky: inconsistent compressed-column pattern");
    if (node_of && (static_cast<int>(node_of->size()) != n ||
                    std::any_of(node_of->begin(), node_of->end(), [](int v) { return v < 0; })))
        throw std::invalid_argument("sparse Cholesky: node_of must give a node (>= 0) for each of the n columns");
    for (int j = 0; j < n; ++j)
        for (int p = column_start[j]; p < column_start[j + 1]; ++p)
            if (row[p] < 0 || row[p] > j || (p > column_start[j] && row[p] <= row[p - 1]) ||
                (p + 1 == column_start[j + 1] && row[p] != j))
                throw std::invalid_argument("sparse Cholesky: column " + std::to_string(j) +
                                            " must hold rows 0..j of the upper triangle, increasing, its diagonal last");
    if (own_ldl && node_of) {
        // The whole analysis without CHOLMOD: AMD on the quotient graph, then the elimination
        // tree and column counts of the own LDL^T. Kept where CHOLMOD would factorise
        // simplicially (by its own rule, on these counts); otherwise CHOLMOD's analysis below.
        const std::vector<int> perm = quotient_amd_ordering(n, column_start, row, *node_of);
        if (!perm.empty()) {
            own_symbolic(perm, column_start, row);
            if (own_flops_ < kSupernodalSwitch * own_nonzeros_) return;
            perm_.clear(), ap_.clear(), ai_.clear(), value_of_.clear(), parent_.clear(), lp_.clear(), pair_.clear();
        }
    }
    auto* c = new cholmod_common;
    cholmod_start(c);
    // Failures are reported through the return values checked below, not printed.
    c->print = 0;
    c->error_handler = nullptr;
    common_ = c;
    const size_t nnz = row.size();
    cholmod_sparse* A = cholmod_allocate_sparse(n, n, nnz, /*sorted=*/1, /*packed=*/1, /*stype=*/1, CHOLMOD_REAL, c);
    if (!A) {
        cholmod_finish(c);
        delete c;
        throw std::runtime_error("sparse Cholesky: CHOLMOD could not allocate the matrix");
    }
    std::copy(column_start.begin(), column_start.end(), static_cast<int*>(A->p));
    std::copy(row.begin(), row.end(), static_cast<int*>(A->i));
    std::fill_n(static_cast<double*>(A->x), nnz, 0.0);
    matrix_ = A;
    cholmod_factor* L = nullptr;
    {
        SerialOpenMP serial;
        L = cholmod_analyze(A, c);
    }
    if (!L || c->status < CHOLMOD_OK) {
        const int status = c->status;  // read before c is freed
        cholmod_free_sparse(&A, c);
        cholmod_finish(c);
        delete c;
        throw std::runtime_error("sparse Cholesky: CHOLMOD's symbolic analysis failed (status " +
                                 std::to_string(status) + ")");
    }
    symbolic_ = L;
    if (!own_ldl || L->is_super) return;
    const int* perm = static_cast<const int*>(L->Perm);
    own_symbolic(std::vector<int>(perm, perm + n), column_start, row);
}

void CholeskyAnalysis::own_symbolic(const std::vector<int>& perm, const std::vector<int>& column_start,
                                    const std::vector<int>& row) {
    const int n = n_;
    const size_t nnz = row.size();
    // The permuted upper triangle: entry (i, j) of A goes to (min, max) of (pinv i, pinv j).
    perm_ = perm;
    std::vector<int> pinv(n);
    for (int k = 0; k < n; ++k) pinv[perm[k]] = k;
    // Columns, and rows within each column, in increasing order: two stable counting sorts (by
    // row, then by column), linear in nnz where a comparison sort was a tenth of a Monte Carlo
    // run's time (measured), one analysis per new cluster.
    std::vector<std::pair<int, int>> permuted(nnz);  // (column, row) of each entry in P A P^T's upper triangle
    std::vector<int> by_row_start(n + 1, 0), by_row(nnz);
    ap_.assign(n + 1, 0);
    for (int j = 0; j < n; ++j)
        for (int p = column_start[j]; p < column_start[j + 1]; ++p) {
            const int a = pinv[row[p]], b = pinv[j];
            permuted[p] = {std::max(a, b), std::min(a, b)};
            ++by_row_start[permuted[p].second + 1];
            ++ap_[permuted[p].first + 1];
        }
    for (int i = 0; i < n; ++i) by_row_start[i + 1] += by_row_start[i];
    for (int j = 0; j < n; ++j) ap_[j + 1] += ap_[j];
    for (int p = 0; p < static_cast<int>(nnz); ++p) by_row[by_row_start[permuted[p].second]++] = p;
    ai_.resize(nnz);
    value_of_.resize(nnz);
    std::vector<int> next(ap_.begin(), ap_.end() - 1);
    for (const int p : by_row) {
        const auto [c, r] = permuted[p];
        ai_[next[c]] = r;
        value_of_[next[c]++] = p;
    }
    // Elimination tree and column counts of L (ldl_symbolic).
    parent_.assign(n, -1);
    std::vector<int> flag(n), lnz(n, 0);
    for (int k = 0; k < n; ++k) {
        flag[k] = k;
        for (int p = ap_[k]; p < ap_[k + 1]; ++p)
            for (int i = ai_[p]; i < k && flag[i] != k; i = parent_[i]) {
                if (parent_[i] == -1) parent_[i] = k;
                ++lnz[i];
                flag[i] = k;
            }
    }
    lp_.assign(n + 1, 0);
    for (int k = 0; k < n; ++k) lp_[k + 1] = lp_[k] + lnz[k];
    // Pairs of rows factorised together: column k + 1 of P A P^T holds column k's rows (k
    // included) and k + 1, as both coordinates of one corner do when the ordering keeps them
    // adjacent; then both rows of L reach the same columns, and row k + 1 column k too.
    pair_.assign(n, 0);
    for (int k = 0; k + 1 < n;) {
        const int rows = ap_[k + 1] - ap_[k];
        const bool same = ap_[k + 2] - ap_[k + 1] == rows + 1 && rows > 0 && ai_[ap_[k + 1] - 1] == k &&
                          ai_[ap_[k + 2] - 1] == k + 1 &&
                          std::equal(ai_.begin() + ap_[k], ai_.begin() + ap_[k + 1], ai_.begin() + ap_[k + 1]);
        pair_[k] = same;
        k += same ? 2 : 1;
    }
    // nnz(L) and the flops of an LL^T factorisation as CHOLMOD counts them (its column counts
    // include the diagonal; flops: the sum of their squares).
    own_nonzeros_ = 0, own_flops_ = 0;
    for (int k = 0; k < n; ++k) {
        const double count = lnz[k] + 1.0;
        own_nonzeros_ += count;
        own_flops_ += count * count;
    }
}

CholeskyAnalysis::~CholeskyAnalysis() {
    auto* c = common_of(common_);
    auto* L = static_cast<cholmod_factor*>(symbolic_);
    auto* A = static_cast<cholmod_sparse*>(matrix_);
    if (!c) return;  // analysed without CHOLMOD
    cholmod_free_factor(&L, c);
    cholmod_free_sparse(&A, c);
    cholmod_finish(c);
    delete c;
}

long CholeskyAnalysis::factor_nonzeros() const {
    return common_ ? static_cast<long>(common_of(common_)->lnz) : static_cast<long>(own_nonzeros_);
}

double CholeskyAnalysis::factor_flops() const { return common_ ? common_of(common_)->fl : own_flops_; }

int CholeskyAnalysis::paired_rows() const { return static_cast<int>(std::count(pair_.begin(), pair_.end(), 1)); }

bool CholeskyAnalysis::supernodal() const { return symbolic_ && static_cast<cholmod_factor*>(symbolic_)->is_super; }

CholeskyFactor::CholeskyFactor(std::shared_ptr<CholeskyAnalysis> analysis) : analysis_(std::move(analysis)) {
    auto* c = common_of(analysis_->common_);
    if (analysis_->own_ldl()) {
        const int n = analysis_->n_;
        li_.resize(analysis_->lp_[n]);
        lx_.resize(analysis_->lp_[n]);
        d_.resize(n), y_.resize(n), y2_.resize(n), lnz_.resize(n), flag_.resize(n), pattern_.resize(n);
        return;
    }
    factor_ = cholmod_copy_factor(static_cast<cholmod_factor*>(analysis_->symbolic_), c);
    if (!factor_) throw std::runtime_error("sparse Cholesky: CHOLMOD could not allocate a factor");
}

CholeskyFactor::~CholeskyFactor() {
    if (!factor_) return;
    auto* L = static_cast<cholmod_factor*>(factor_);
    cholmod_free_factor(&L, common_of(analysis_->common_));
}

int CholeskyFactor::size() const { return analysis_->n_; }

bool CholeskyFactor::factorize(const std::vector<double>& values) {
    auto* c = common_of(analysis_->common_);
    auto* A = static_cast<cholmod_sparse*>(analysis_->matrix_);
    if (values.size() != analysis_->nnz_) throw std::invalid_argument("sparse Cholesky: values do not match the pattern");
    if (analysis_->own_ldl()) {
        // Up-looking LDL^T of P A P^T, row k of L from the elimination tree (ldl_numeric); rows
        // k, k + 1 of a pair (CholeskyAnalysis::pair_) together: one walk of the tree and one
        // pass over each column of L for both, the same operations in the same order as two
        // single rows (the factor is the same to the last bit).
        const CholeskyAnalysis& a = *analysis_;
        const int n = a.n_;
        ok_ = true;
        for (int k = 0; k < n;) {
            const bool pair = a.pair_[k];
            y_[k] = 0.0;
            int top = n;
            flag_[k] = k;
            lnz_[k] = 0;
            for (int p = a.ap_[k]; p < a.ap_[k + 1]; ++p) {
                int i = a.ai_[p];
                y_[i] += values[a.value_of_[p]];
                int len = 0;
                for (; flag_[i] != k; i = a.parent_[i]) {
                    pattern_[len++] = i;
                    flag_[i] = k;
                }
                while (len > 0) pattern_[--top] = pattern_[--len];
            }
            // Row k + 1 of a pair: its column of A is row k's rows and k, k + 1 (the pair's test),
            // so its tree walk is row k's; its entries in rows k and k + 1 are kept apart.
            double y2_k = 0.0, d2 = 0.0;
            if (pair) {
                flag_[k + 1] = k + 1;
                lnz_[k + 1] = 0;
                for (int p = a.ap_[k + 1]; p < a.ap_[k + 2]; ++p) {
                    const int i = a.ai_[p];
                    if (i == k) {
                        y2_k += values[a.value_of_[p]];
                    } else if (i == k + 1) {
                        d2 += values[a.value_of_[p]];
                    } else {
                        y2_[i] += values[a.value_of_[p]];
                    }
                }
            }
            d_[k] = y_[k];
            y_[k] = 0.0;
            for (; top < n; ++top) {
                const int i = pattern_[top];
                const double yi = y_[i];
                y_[i] = 0.0;
                const int p2 = a.lp_[i] + lnz_[i];
                const double l_ki = yi / d_[i];
                if (!pair) {
                    for (int p = a.lp_[i]; p < p2; ++p) y_[li_[p]] -= lx_[p] * yi;
                    d_[k] -= l_ki * yi;
                    li_[p2] = k;
                    lx_[p2] = l_ki;
                    ++lnz_[i];
                    continue;
                }
                const double zi = y2_[i];
                y2_[i] = 0.0;
                for (int p = a.lp_[i]; p < p2; ++p) {
                    y_[li_[p]] -= lx_[p] * yi;
                    y2_[li_[p]] -= lx_[p] * zi;
                }
                const double l_k1i = zi / d_[i];
                d_[k] -= l_ki * yi;
                y2_k -= l_ki * zi;  // row k's entry of column i, as a single row k + 1 would meet it
                d2 -= l_k1i * zi;
                li_[p2] = k, lx_[p2] = l_ki;
                li_[p2 + 1] = k + 1, lx_[p2 + 1] = l_k1i;
                lnz_[i] += 2;
            }
            if (!(d_[k] > 0)) {  // positive definite: every pivot positive
                ok_ = false;
                break;
            }
            if (!pair) {
                ++k;
                continue;
            }
            // Row k + 1's last column, k (the ancestor of every other column it reaches).
            const double l = y2_k / d_[k];
            d2 -= l * y2_k;
            li_[a.lp_[k]] = k + 1, lx_[a.lp_[k]] = l;
            lnz_[k] = 1;
            d_[k + 1] = d2;
            if (!(d2 > 0)) {
                ok_ = false;
                break;
            }
            k += 2;
        }
        return ok_;
    }
    std::copy(values.begin(), values.end(), static_cast<double*>(A->x));
    auto* L = static_cast<cholmod_factor*>(factor_);
    int status = 0;
    {
        SerialOpenMP serial;
        std::lock_guard<std::mutex> blas(blas_lock());
        status = cholmod_factorize(A, L, c);
    }
    ok_ = status && c->status == CHOLMOD_OK && L->minor == L->n;
    if (ok_ && !L->is_super && !L->is_ll) {
        // Simplicial LDL^T: positive definite means every pivot positive (CHOLMOD only rejects zero ones).
        const int* Lp = static_cast<const int*>(L->p);
        const double* Lx = static_cast<const double*>(L->x);
        for (size_t j = 0; j < L->n && ok_; ++j) ok_ = Lx[Lp[j]] > 0;
    }
    return ok_;
}

double CholeskyFactor::pivot_ratio() const {
    if (!ok_) return 0.0;
    double lo = std::numeric_limits<double>::infinity(), hi = 0;
    auto take = [&](double pivot) { lo = std::min(lo, pivot), hi = std::max(hi, pivot); };
    if (analysis_->own_ldl()) {
        for (const double pivot : d_) take(pivot);
        return hi > 0 ? lo / hi : 0.0;
    }
    const auto* L = static_cast<const cholmod_factor*>(factor_);
    const double* x = static_cast<const double*>(L->x);
    if (L->is_super) {
        const int* super = static_cast<const int*>(L->super);
        const int* pi = static_cast<const int*>(L->pi);
        const int* px = static_cast<const int*>(L->px);
        for (size_t s = 0; s < L->nsuper; ++s) {
            const int width = super[s + 1] - super[s], rows = pi[s + 1] - pi[s];
            for (int j = 0; j < width; ++j) take(x[px[s] + j + j * rows] * x[px[s] + j + j * rows]);
        }
    } else {
        const int* p = static_cast<const int*>(L->p);
        for (size_t j = 0; j < L->n; ++j) take(L->is_ll ? x[p[j]] * x[p[j]] : x[p[j]]);
    }
    return hi > 0 ? lo / hi : 0.0;
}

Eigen::VectorXd CholeskyFactor::solve(const Eigen::VectorXd& b) const {
    if (!ok_) throw std::runtime_error("sparse Cholesky: solve with a failed factorisation");
    auto* c = common_of(analysis_->common_);
    const int n = size();
    if (b.size() != n) throw std::invalid_argument("sparse Cholesky: right-hand side has the wrong size");
    if (analysis_->own_ldl()) {
        const CholeskyAnalysis& a = *analysis_;
        Eigen::VectorXd x(n);
        for (int k = 0; k < n; ++k) x[k] = b[a.perm_[k]];
        const int* lp = a.lp_.data();
        ldl_solve_in_place(
            n, [lp](int j) { return lp[j]; }, [lp](int j) { return lp[j + 1]; }, li_.data(), lx_.data(),
            [this](int j) { return d_[j]; }, x);
        Eigen::VectorXd out(n);
        for (int k = 0; k < n; ++k) out[a.perm_[k]] = x[k];
        return out;
    }
    cholmod_dense rhs = dense_view(b);
    cholmod_dense* x = nullptr;
    {
        SerialOpenMP serial;
        std::lock_guard<std::mutex> blas(blas_lock());
        x = cholmod_solve(CHOLMOD_A, static_cast<cholmod_factor*>(factor_), &rhs, c);
    }
    if (!x) throw std::runtime_error("sparse Cholesky: CHOLMOD's solve failed");
    return take_dense(x, c);
}

}  // namespace pyfrustrate

namespace pyfrustrate {

namespace {
cholmod_factor* factor_of(void* p) { return static_cast<cholmod_factor*>(p); }

cholmod_common* start_common() {
    auto* c = new cholmod_common;
    cholmod_start(c);
    c->print = 0;
    c->error_handler = nullptr;
    // Natural order (the caller's rows are already in elimination order), simplicial LDL^T: the
    // form CHOLMOD's Modify routines work on.
    c->nmethods = 1;
    c->method[0].ordering = CHOLMOD_NATURAL;
    c->postorder = 0;
    c->supernodal = CHOLMOD_SIMPLICIAL;
    c->final_ll = 0;
    // Room left in each column when the factor is unpacked (grow1 * nz + grow2 entries) and by
    // how much the whole grows when a column outgrows it (grow0).
    c->grow1 = 1.0;
    c->grow2 = 16;
    c->grow0 = 1.5;
    return c;
}

void finish_common(cholmod_common* c) {
    cholmod_finish(c);
    delete c;
}
}  // namespace

std::unique_ptr<ModifiableFactor> ModifiableFactor::make(int n, const std::vector<int>& column_start,
                                                         const std::vector<int>& row, const std::vector<double>& values,
                                                         int spare, std::vector<int>& row_of_dof) {
    if (n < 1 || spare < 0) throw std::invalid_argument("modifiable factor: empty matrix or negative spare");
    if (static_cast<int>(column_start.size()) != n + 1 || column_start.back() != static_cast<int>(row.size()) ||
        values.size() != row.size())
        throw std::invalid_argument("modifiable factor: inconsistent compressed-column pattern");
    std::unique_ptr<ModifiableFactor> f(new ModifiableFactor);
    cholmod_common* c = start_common();
    f->common_ = c;
    f->n_ = n + spare;
    SerialOpenMP serial;
    // The fill-reducing order of the matrix itself (AMD), spare rows after it.
    cholmod_sparse pattern_view;
    pattern_view.nrow = pattern_view.ncol = n;
    pattern_view.nzmax = row.size();
    pattern_view.p = const_cast<int*>(column_start.data());
    pattern_view.i = const_cast<int*>(row.data());
    pattern_view.nz = nullptr;
    pattern_view.x = const_cast<double*>(values.data());
    pattern_view.z = nullptr;
    pattern_view.stype = 1;
    pattern_view.itype = CHOLMOD_INT;
    pattern_view.xtype = CHOLMOD_REAL;
    pattern_view.dtype = CHOLMOD_DOUBLE;
    pattern_view.sorted = 1;
    pattern_view.packed = 1;
    std::vector<int> perm(n);
    if (!cholmod_amd(&pattern_view, nullptr, 0, perm.data(), c)) return nullptr;
    row_of_dof.assign(n, 0);
    for (int k = 0; k < n; ++k) row_of_dof[perm[k]] = k;
    cholmod_triplet* t = cholmod_allocate_triplet(f->n_, f->n_, row.size() + spare, 1, CHOLMOD_REAL, c);
    if (!t) return nullptr;
    auto* ti = static_cast<int*>(t->i);
    auto* tj = static_cast<int*>(t->j);
    auto* tx = static_cast<double*>(t->x);
    size_t k = 0;
    for (int j = 0; j < n; ++j)
        for (int p = column_start[j]; p < column_start[j + 1]; ++p, ++k) {
            const int a = row_of_dof[row[p]], b = row_of_dof[j];
            ti[k] = std::min(a, b), tj[k] = std::max(a, b), tx[k] = values[p];
        }
    for (int s = 0; s < spare; ++s, ++k) ti[k] = tj[k] = n + s, tx[k] = 1.0;
    t->nnz = k;
    cholmod_sparse* A = cholmod_triplet_to_sparse(t, k, c);
    cholmod_free_triplet(&t, c);
    if (!A) return nullptr;
    cholmod_factor* L = cholmod_analyze(A, c);
    const bool ok = L && cholmod_factorize(A, L, c) && c->status == CHOLMOD_OK && L->minor == L->n;
    cholmod_free_sparse(&A, c);
    f->factor_ = L;
    // Unpacked, with room in every column for the entries rows added later bring (a row added
    // last puts one entry in each column of its row's pattern): without it, CHOLMOD moved
    // columns and repacked the whole factor on most row additions (a large share of a child's
    // relaxation in a profile of the 817-particle disk).
    if (ok && !cholmod_change_factor(CHOLMOD_REAL, /*to_ll=*/0, /*to_super=*/0, /*to_packed=*/0, /*to_monotonic=*/1, L, c))
        return nullptr;
    f->in_use_.assign(f->n_, 0);
    std::fill_n(f->in_use_.begin(), n, 1);
    if (!ok || !f->positive_definite()) return nullptr;
    return f;
}

std::unique_ptr<ModifiableFactor> ModifiableFactor::copy() const {
    std::unique_ptr<ModifiableFactor> f(new ModifiableFactor);
    cholmod_common* c = start_common();
    f->common_ = c;
    f->n_ = n_;
    f->in_use_ = in_use_;
    f->factor_ = cholmod_copy_factor(factor_of(factor_), c);
    if (!f->factor_) throw std::runtime_error("modifiable factor: CHOLMOD could not copy the factor");
    return f;
}

ModifiableFactor::~ModifiableFactor() {
    auto* c = common_of(common_);
    if (!c) return;
    auto* L = factor_of(factor_);
    if (L) cholmod_free_factor(&L, c);
    finish_common(c);
}

int ModifiableFactor::take_free_row() {
    for (int k = n_ - 1; k >= 0; --k)
        if (!in_use_[k]) {
            in_use_[k] = 1;
            return k;
        }
    return -1;
}

bool ModifiableFactor::add_row(int k, std::vector<std::pair<int, double>> column) {
    auto* c = common_of(common_);
    std::sort(column.begin(), column.end());
    cholmod_sparse* R = cholmod_allocate_sparse(n_, 1, column.size(), 1, 1, 0, CHOLMOD_REAL, c);
    if (!R) return false;
    auto* rp = static_cast<int*>(R->p);
    auto* ri = static_cast<int*>(R->i);
    auto* rx = static_cast<double*>(R->x);
    rp[0] = 0;
    int m = 0;
    for (const auto& [r, v] : column) {
        if (m > 0 && ri[m - 1] == r) {
            rx[m - 1] += v;
            continue;
        }
        ri[m] = r, rx[m] = v, ++m;
    }
    rp[1] = m;
    int ok = 0;
    {
        SerialOpenMP serial;
        ok = cholmod_rowadd(k, R, factor_of(factor_), c);
    }
    cholmod_free_sparse(&R, c);
    in_use_[k] = 1;
    return ok && c->status == CHOLMOD_OK;
}

bool ModifiableFactor::delete_row(int k) {
    auto* c = common_of(common_);
    int ok = 0;
    {
        SerialOpenMP serial;
        ok = cholmod_rowdel(k, nullptr, factor_of(factor_), c);
    }
    in_use_[k] = 0;
    return ok && c->status == CHOLMOD_OK;
}

bool ModifiableFactor::update(const std::vector<int>& rows, const Eigen::MatrixXd& V, bool add) {
    if (V.cols() == 0) return true;
    auto* c = common_of(common_);
    std::vector<int> order(rows.size());
    for (size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int>(i);
    std::sort(order.begin(), order.end(), [&](int a, int b) { return rows[a] < rows[b]; });
    const int m = static_cast<int>(V.cols()), r = static_cast<int>(rows.size());
    cholmod_sparse* C = cholmod_allocate_sparse(n_, m, static_cast<size_t>(r) * m, 1, 1, 0, CHOLMOD_REAL, c);
    if (!C) return false;
    auto* cp = static_cast<int*>(C->p);
    auto* ci = static_cast<int*>(C->i);
    auto* cx = static_cast<double*>(C->x);
    for (int j = 0; j < m; ++j) {
        cp[j] = j * r;
        for (int q = 0; q < r; ++q) ci[j * r + q] = rows[order[q]], cx[j * r + q] = V(order[q], j);
    }
    cp[m] = m * r;
    int ok = 0;
    {
        SerialOpenMP serial;
        ok = cholmod_updown(add ? 1 : 0, C, factor_of(factor_), c);
    }
    cholmod_free_sparse(&C, c);
    return ok && c->status == CHOLMOD_OK;
}

Eigen::VectorXd ModifiableFactor::solve(const Eigen::VectorXd& b) const {
    // CHOLMOD's solve: ldl_solve_in_place on its arrays was slower on the 817-particle disk (a
    // memory-bound solve; CHOLMOD's simplicial one takes chains of columns of like pattern, such
    // as a corner's two rows, in one pass).
    auto* c = common_of(common_);
    if (b.size() != n_) throw std::invalid_argument("modifiable factor: right-hand side has the wrong size");
    cholmod_dense rhs = dense_view(b);
    cholmod_dense* x = nullptr;
    {
        SerialOpenMP serial;
        x = cholmod_solve(CHOLMOD_LDLt, factor_of(factor_), &rhs, c);
    }
    if (!x) throw std::runtime_error("modifiable factor: CHOLMOD's solve failed");
    return take_dense(x, c);
}

long ModifiableFactor::nonzeros() const {
    const auto* L = factor_of(factor_);
    const int* nz = static_cast<const int*>(L->nz);
    long total = 0;
    for (size_t j = 0; j < L->n; ++j) total += nz[j];
    return total;
}

bool ModifiableFactor::positive_definite() const {
    const auto* L = factor_of(factor_);
    if (L->is_super || L->is_ll) return false;
    const int* p = static_cast<const int*>(L->p);
    const double* x = static_cast<const double*>(L->x);
    for (size_t j = 0; j < L->n; ++j)
        if (!(x[p[j]] > 0) || !std::isfinite(x[p[j]])) return false;
    return true;
}

}  // namespace pyfrustrate
