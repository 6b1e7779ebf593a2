#include <mbd/kit/own_order_fill.hpp>

#include <Eigen/OrderingMethods>
#include <Eigen/SparseCholesky>

#include <vector>

namespace mbd {

namespace {

// The symbolic analysis of Eigen's L D L^T, which counts each column of L from the elimination
// tree before anything is factored; the count is its factor's reserved size.
class SymbolicCount : public Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Lower, Eigen::NaturalOrdering<int>> {
public:
    long entries(const Eigen::SparseMatrix<double>& symmetric) {
        analyzePattern(symmetric);
        return static_cast<long>(m_matrix.nonZeros());  // strictly below the diagonal (L D L^T)
    }
};

}  // namespace

long own_order_cholesky_entries(const Eigen::SparseMatrix<double>& K) {
    const auto n = K.rows();
    std::vector<Eigen::Triplet<double>> pattern;
    pattern.reserve(static_cast<size_t>(2 * K.nonZeros() + n));
    for (Eigen::Index c = 0; c < K.outerSize(); ++c)
        for (Eigen::SparseMatrix<double>::InnerIterator it(K, c); it; ++it) {
            pattern.emplace_back(static_cast<int>(it.row()), static_cast<int>(c), 1.0);
            pattern.emplace_back(static_cast<int>(c), static_cast<int>(it.row()), 1.0);
        }
    for (Eigen::Index k = 0; k < n; ++k) pattern.emplace_back(static_cast<int>(k), static_cast<int>(k), 1.0);
    Eigen::SparseMatrix<double> symmetric(n, n);
    symmetric.setFromTriplets(pattern.begin(), pattern.end());
    SymbolicCount count;
    return count.entries(symmetric) + static_cast<long>(n);
}

}  // namespace mbd
