// Sparse Cholesky factorisation through CHOLMOD (SuiteSparse): the symbolic analysis (fill-
// reducing ordering, elimination tree, supernodes) is done once per sparsity pattern and shared
// by every numeric factorisation of matrices with that pattern. Large networks get CHOLMOD's
// supernodal LL^T (dense BLAS on the supernodes), small ones its simplicial factorisation:
// CHOLMOD chooses from the flop count of the analysis.
//
// Not thread-safe: factors sharing one analysis share its CHOLMOD workspace.
#pragma once

#include <Eigen/Dense>
#include <memory>
#include <vector>

namespace pyfrustrate {

class CholeskyAnalysis;

// One numeric factorisation on a shared analysis.
class CholeskyFactor {
   public:
    explicit CholeskyFactor(std::shared_ptr<CholeskyAnalysis> analysis);
    ~CholeskyFactor();
    CholeskyFactor(const CholeskyFactor&) = delete;
    CholeskyFactor& operator=(const CholeskyFactor&) = delete;

    // Factorises the matrix with these values on the analysis' pattern (upper triangle, CSC).
    // Returns false if it is not positive definite (the factor is then unusable until the next
    // successful call).
    bool factorize(const std::vector<double>& values);
    bool ok() const { return ok_; }
    // A^-1 b.
    Eigen::VectorXd solve(const Eigen::VectorXd& b) const;
    int size() const;
    // Smallest over largest pivot of the last factorisation (the D of LDL^T, or diag(L)^2):
    // near round-off, the matrix is singular in all but name (a floppy mode).
    double pivot_ratio() const;

   private:
    std::shared_ptr<CholeskyAnalysis> analysis_;
    void* factor_ = nullptr;  // cholmod_factor*
    bool ok_ = false;
    // The analysis' own LDL^T (CholeskyAnalysis::own_ldl): L by columns, D, and workspace.
    std::vector<int> li_, lnz_, flag_, pattern_;
    std::vector<double> lx_, d_, y_, y2_;  // y2_: the second row of a pair
};

// The symbolic analysis of one pattern: upper triangle of a symmetric n x n matrix in
// compressed columns (column_start of size n + 1, row indices sorted within each column).
class CholeskyAnalysis {
   public:
    // own_ldl: where CHOLMOD's analysis is simplicial, factorise with an up-looking LDL^T of our
    // own on CHOLMOD's fill-reducing ordering (Davis' LDL algorithm) instead of CHOLMOD's: the
    // permuted pattern is made once here, where CHOLMOD permutes (transposes) the matrix before
    // every factorisation. Same ordering, same factor to round-off.
    // node_of (own_ldl only): a node for each column, columns of one node touching the same
    // entries (a network's corner and its two coordinates). The fill-reducing ordering is then
    // AMD's on the nodes' quotient graph, and where the factorisation is simplicial CHOLMOD is
    // not called at all: the Monte Carlo's clusters, each analysed once, pay a fraction of the
    // symbolic set-up.
    CholeskyAnalysis(int n, const std::vector<int>& column_start, const std::vector<int>& row, bool own_ldl = false,
                     const std::vector<int>* node_of = nullptr);
    ~CholeskyAnalysis();
    CholeskyAnalysis(const CholeskyAnalysis&) = delete;
    CholeskyAnalysis& operator=(const CholeskyAnalysis&) = delete;
    int size() const { return n_; }
    long factor_nonzeros() const;  // nnz(L) predicted by the analysis
    double factor_flops() const;   // floating-point operations of one numeric factorisation
    bool supernodal() const;
    bool own_ldl() const { return !perm_.empty(); }
    bool cholmod_analysed() const { return common_ != nullptr; }
    int paired_rows() const;  // own LDL^T: pairs of rows factorised together

   private:
    friend class CholeskyFactor;
    // The own LDL^T's set-up on the ordering perm.
    void own_symbolic(const std::vector<int>& perm, const std::vector<int>& column_start, const std::vector<int>& row);
    int n_;
    std::size_t nnz_;           // entries of the pattern
    double own_nonzeros_ = 0, own_flops_ = 0;  // analysed without CHOLMOD: its nnz(L) and flops
    void* common_ = nullptr;    // cholmod_common* (nullptr: analysed without CHOLMOD)
    void* matrix_ = nullptr;    // cholmod_sparse* (pattern; values written before each factorisation)
    void* symbolic_ = nullptr;  // cholmod_factor*
    // own_ldl: the ordering, the upper triangle of P A P^T in compressed columns with the index
    // of each entry's value in the caller's pattern, the elimination tree and column pointers of L.
    // pair_[k]: rows k and k + 1 have the same pattern below the diagonal, factorised together.
    std::vector<int> perm_, ap_, ai_, value_of_, parent_, lp_;
    std::vector<char> pair_;
};

}  // namespace pyfrustrate

namespace pyfrustrate {

// A simplicial LDL^T factor that is modified in place instead of refactorised (CHOLMOD's Modify
// module): rows added and deleted, low-rank updates and downdates. The Monte Carlo's clusters
// differ from the one they came from by a particle or a few, and so do their Hessians: a few
// rows and a block of rank <= 2 x corners per particle. Rows are numbered in elimination order
// (the caller's degrees of freedom were permuted by AMD when the factor was made, and CHOLMOD
// runs in natural order), with `spare` identity rows appended for the corners of particles that
// join later: a row added last creates no fill in the columns before it.
class ModifiableFactor {
   public:
    // Factorises the symmetric matrix given by its upper triangle in compressed columns on n
    // degrees of freedom (rows sorted within each column), plus `spare` identity rows. Returns
    // nullptr where it is not positive definite. row_of_dof receives each dof's row.
    static std::unique_ptr<ModifiableFactor> make(int n, const std::vector<int>& column_start,
                                                  const std::vector<int>& row, const std::vector<double>& values,
                                                  int spare, std::vector<int>& row_of_dof);
    std::unique_ptr<ModifiableFactor> copy() const;
    ~ModifiableFactor();
    ModifiableFactor(const ModifiableFactor&) = delete;
    ModifiableFactor& operator=(const ModifiableFactor&) = delete;

    int rows() const { return n_; }
    // An identity row (spare, or deleted), preferring the last; -1 if none is left.
    int take_free_row();
    // Row k (an identity row) becomes the matrix column given by (row, value) pairs, the
    // diagonal included; the entries must lie in rows in use or k itself.
    bool add_row(int k, std::vector<std::pair<int, double>> column);
    // Row k becomes an identity row again (its degree of freedom leaves the matrix).
    bool delete_row(int k);
    // A + sign * V V^T for the columns of V, nonzero only in `rows` (V is rows.size() x m).
    bool update(const std::vector<int>& rows, const Eigen::MatrixXd& V, bool add);
    // A^-1 b, b and the result in rows (identity rows pass b through).
    Eigen::VectorXd solve(const Eigen::VectorXd& b) const;
    long nonzeros() const;
    // Every pivot of D positive (the modified matrix is still positive definite).
    bool positive_definite() const;

   private:
    ModifiableFactor() = default;
    int n_ = 0;
    void* common_ = nullptr;  // cholmod_common*, one per factor (its workspace)
    void* factor_ = nullptr;  // cholmod_factor*, simplicial LDL^T
    std::vector<char> in_use_;
};

}  // namespace pyfrustrate
