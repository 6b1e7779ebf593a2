// What every ANCF body of this plugin shares: a straight reference line meshed into equal
// elements, points named by their arc length x in [0, L] (the material parameter), a node at
// each element end, a constant mass matrix, and a position linear in the coordinates (so the
// gravity potential is -Q_g^T q), and a centre line r(x) = sum_k h_k(x) e_k of cubic Hermite
// shape functions h_k over four nodal vectors e_k of each element, which makes the body a curve
// (sdk body_curve.hpp) for a joint that slides along it. Header-only, shared by the types of
// this plugin.
#pragma once

#include "beam_keys.hpp"

#include "shared/hermite.hpp"

#include <mbd/sdk/body.hpp>
#include <mbd/sdk/body_curve.hpp>
#include <mbd/sdk/text.hpp>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace mbd::ancf {

class MeshedBeam : public FlexibleBody, public BodyCurve {
public:
    bool constant_mass() const override { return true; }
    void mass_matrix(const Eigen::VectorXd& /*q*/, Eigen::MatrixXd& M) const override { M = mass_; }
    double gravity_potential(const Eigen::VectorXd& q, const Vec3& g) const override {
        Eigen::VectorXd Q(coordinates());  // r is linear in q: the integral of g . r dm is Q_g^T q
        gravity_forces(q, g, Q);
        return -Q.dot(q);
    }

    int material_parameters() const override { return 1; }
    void check_material_point(const double* xi) const override {
        const double slack = 1e-12 * line_.length;
        if (!(xi[0] >= -slack && xi[0] <= line_.length + slack))
            throw InputError("", "the point at arc length " + format_number(xi[0]) + " lies outside the beam [0, " +
                                     format_number(line_.length) + "]");
    }
    int node_count() const override { return line_.elements + 1; }
    std::vector<double> node_parameters(int node) const override { return {node * line_.element_length()}; }

    // --- the centre line as a curve (sdk body_curve.hpp): S = [h_k I] does not depend on q, so
    // rdot_s = S_s v and the bias is zero
    int curve_pieces() const override { return line_.elements; }
    double curve_break(int k) const override { return k * line_.element_length(); }
    void curve_point(const Eigen::VectorXd& q, const Eigen::VectorXd& v, double s, CurvePoint& out) const override {
        const Located at = locate(s);
        const double l = line_.element_length();
        const beam::Shape f = beam::shape(at.xi, l);
        // the Hermite shapes' third derivatives (constant on an element)
        const Eigen::Vector4d ddds(12 / (l * l * l), 6 / (l * l), -12 / (l * l * l), 6 / (l * l));
        out = CurvePoint{};
        for (int k = 0; k < 4; ++k) {
            const int c = centre_column(at.element, k);
            for (int d = 0; d < centre_.dimension; ++d) {
                out.r[d] += f.s[k] * q[c + d];
                out.r_s[d] += f.ds[k] * q[c + d];
                out.r_ss[d] += f.dds[k] * q[c + d];
                out.r_sss[d] += ddds[k] * q[c + d];
                out.rdot[d] += f.s[k] * v[c + d];
                out.rdot_s[d] += f.ds[k] * v[c + d];
                out.rdot_ss[d] += f.dds[k] * v[c + d];
            }
        }
    }
    void add_curve_jacobian(const Eigen::VectorXd& /*q*/, double s, const Vec3& w, Eigen::Ref<Eigen::MatrixXd> J,
                            int row) const override {
        const Located at = locate(s);
        const beam::Shape f = beam::shape(at.xi, line_.element_length());
        add_rows(at.element, f.s, w, J, row);
    }
    void add_curve_slope_jacobian(const Eigen::VectorXd& /*q*/, double s, const Vec3& w, Eigen::Ref<Eigen::MatrixXd> J,
                                  int row) const override {
        const Located at = locate(s);
        const beam::Shape f = beam::shape(at.xi, line_.element_length());
        add_rows(at.element, f.ds, w, J, row);
    }

protected:
    // Where the centre line's nodal vectors e_0..e_3 of element j start: stride * j + first[k],
    // each of `dimension` coordinates.
    struct CentreLine {
        int dimension;
        int stride;
        int first[4];
    };
    MeshedBeam(BeamLine line, CentreLine centre) : line_(std::move(line)), centre_(centre) {}
    int centre_column(int element, int k) const { return centre_.stride * element + centre_.first[k]; }
    // J(row, :) += w^T [h_k I] over the element's centre-line vectors, h the shapes or a derivative
    void add_rows(int element, const Eigen::Vector4d& h, const Vec3& w, Eigen::Ref<Eigen::MatrixXd> J, int row) const {
        for (int k = 0; k < 4; ++k)
            for (int d = 0; d < centre_.dimension; ++d) J(row, centre_column(element, k) + d) += h[k] * w[d];
    }

    struct Located {
        int element;
        double xi;  // in [0, 1] along the element
    };
    Located locate(double x) const {
        const double l = line_.element_length();
        const int j = std::clamp(static_cast<int>(std::floor(x / l)), 0, line_.elements - 1);
        return {j, x / l - j};
    }
    // The mesh's mass matrix from one element's, each element's coordinates starting `stride` after
    // the previous one's (the coordinates of a node).
    template <class ElementMatrix>
    void assemble_mass(const ElementMatrix& element, int stride) {
        mass_.setZero(coordinates(), coordinates());
        const int m = static_cast<int>(element.rows());
        for (int j = 0; j < line_.elements; ++j) mass_.block(stride * j, stride * j, m, m) += element;
    }

    // The mesh's strain energy, elastic forces (-dU/dq) and their Jacobian from one element's
    // energy(q_e, gradient or nullptr, Hessian or nullptr), each element's N coordinates starting
    // `stride` after the previous one's.
    template <int N>
    using ElementVector = Eigen::Matrix<double, N, 1>;
    template <int N>
    using ElementMatrix = Eigen::Matrix<double, N, N>;
    template <int N, class Energy>
    double mesh_strain_energy(const Eigen::VectorXd& q, int stride, const Energy& energy) const {
        double U = 0.0;
        for (int j = 0; j < line_.elements; ++j) U += energy(q.segment<N>(stride * j), nullptr, nullptr);
        return U;
    }
    template <int N, class Energy>
    void mesh_elastic_forces(const Eigen::VectorXd& q, int stride, const Energy& energy, Eigen::Ref<Eigen::VectorXd> Q) const {
        Q.setZero();
        ElementVector<N> gradient;
        for (int j = 0; j < line_.elements; ++j) {
            energy(q.segment<N>(stride * j), &gradient, nullptr);
            Q.segment<N>(stride * j) -= gradient;
        }
    }
    template <int N, class Energy>
    void mesh_elastic_jacobian(const Eigen::VectorXd& q, int stride, const Energy& energy,
                               Eigen::Ref<Eigen::MatrixXd> dQ_dq) const {
        dQ_dq.setZero();
        ElementMatrix<N> hessian;
        for (int j = 0; j < line_.elements; ++j) {
            energy(q.segment<N>(stride * j), nullptr, &hessian);
            dQ_dq.block<N, N>(stride * j, stride * j) -= hessian;
        }
    }

    BeamLine line_;
    CentreLine centre_;
    Eigen::MatrixXd mass_;
};

// A MeshedBeam of N-coordinate elements, each starting `Stride` after the previous one, whose
// strain energy, elastic forces and stiffness are assembled from Derived's
// element_energy(q_e, gradient or nullptr, Hessian or nullptr).
template <class Derived, int N, int Stride>
class MeshedBeamOf : public MeshedBeam {
public:
    double strain_energy(const Eigen::VectorXd& q) const override { return mesh_strain_energy<N>(q, Stride, energy()); }
    void elastic_forces(const Eigen::VectorXd& q, Eigen::Ref<Eigen::VectorXd> Q) const override {
        mesh_elastic_forces<N>(q, Stride, energy(), Q);
    }
    void elastic_jacobian(const Eigen::VectorXd& q, Eigen::Ref<Eigen::MatrixXd> dQ_dq) const override {
        mesh_elastic_jacobian<N>(q, Stride, energy(), dQ_dq);
    }

protected:
    using MeshedBeam::MeshedBeam;

private:
    auto energy() const {
        return [this](const ElementVector<N>& qe, ElementVector<N>* gradient, ElementMatrix<N>* hessian) {
            return static_cast<const Derived*>(this)->element_energy(qe, gradient, hessian);
        };
    }
};

}  // namespace mbd::ancf
