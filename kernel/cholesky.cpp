#include "cholesky.hpp"

#include <cholmod.h>

#include <algorithm>
#include <limits>
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

}  // namespace

CholeskyAnalysis::CholeskyAnalysis(int n, const std::vector<int>& column_start, const std::vector<int>& row) : n_(n) {
    if (n < 1) throw std::invalid_argument("sparse Cholesky: empty matrix");
    if (static_cast<int>(column_start.size()) != n + 1 || column_start.back() != static_cast<int>(row.size()))
        throw std::invalid_argument("sparse Cholesky: inconsistent compressed-column pattern");
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
        cholmod_free_sparse(&A, c);
        cholmod_finish(c);
        delete c;
        throw std::runtime_error("sparse Cholesky: CHOLMOD's symbolic analysis failed (status " +
                                 std::to_string(c->status) + ")");
    }
    symbolic_ = L;
}

CholeskyAnalysis::~CholeskyAnalysis() {
    auto* c = common_of(common_);
    auto* L = static_cast<cholmod_factor*>(symbolic_);
    auto* A = static_cast<cholmod_sparse*>(matrix_);
    cholmod_free_factor(&L, c);
    cholmod_free_sparse(&A, c);
    cholmod_finish(c);
    delete c;
}

long CholeskyAnalysis::factor_nonzeros() const { return static_cast<long>(common_of(common_)->lnz); }

double CholeskyAnalysis::factor_flops() const { return common_of(common_)->fl; }

bool CholeskyAnalysis::supernodal() const { return static_cast<cholmod_factor*>(symbolic_)->is_super; }

CholeskyFactor::CholeskyFactor(std::shared_ptr<CholeskyAnalysis> analysis) : analysis_(std::move(analysis)) {
    auto* c = common_of(analysis_->common_);
    factor_ = cholmod_copy_factor(static_cast<cholmod_factor*>(analysis_->symbolic_), c);
    if (!factor_) throw std::runtime_error("sparse Cholesky: CHOLMOD could not allocate a factor");
}

CholeskyFactor::~CholeskyFactor() {
    auto* L = static_cast<cholmod_factor*>(factor_);
    cholmod_free_factor(&L, common_of(analysis_->common_));
}

int CholeskyFactor::size() const { return analysis_->n_; }

bool CholeskyFactor::factorize(const std::vector<double>& values) {
    auto* c = common_of(analysis_->common_);
    auto* A = static_cast<cholmod_sparse*>(analysis_->matrix_);
    if (values.size() != A->nzmax) throw std::invalid_argument("sparse Cholesky: values do not match the pattern");
    std::copy(values.begin(), values.end(), static_cast<double*>(A->x));
    auto* L = static_cast<cholmod_factor*>(factor_);
    int status = 0;
    {
        SerialOpenMP serial;
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
    const auto* L = static_cast<const cholmod_factor*>(factor_);
    const double* x = static_cast<const double*>(L->x);
    double lo = std::numeric_limits<double>::infinity(), hi = 0;
    auto take = [&](double pivot) { lo = std::min(lo, pivot), hi = std::max(hi, pivot); };
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
    cholmod_dense rhs;
    rhs.nrow = n;
    rhs.ncol = 1;
    rhs.nzmax = n;
    rhs.d = n;
    rhs.x = const_cast<double*>(b.data());
    rhs.z = nullptr;
    rhs.xtype = CHOLMOD_REAL;
    rhs.dtype = CHOLMOD_DOUBLE;
    cholmod_dense* x = nullptr;
    {
        SerialOpenMP serial;
        x = cholmod_solve(CHOLMOD_A, static_cast<cholmod_factor*>(factor_), &rhs, c);
    }
    if (!x) throw std::runtime_error("sparse Cholesky: CHOLMOD's solve failed");
    Eigen::VectorXd out = Eigen::Map<const Eigen::VectorXd>(static_cast<double*>(x->x), n);
    cholmod_free_dense(&x, c);
    return out;
}

}  // namespace pyfrustrate
