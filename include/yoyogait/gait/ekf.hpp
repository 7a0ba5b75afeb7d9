/// @file gait/ekf.hpp
/// @brief The gait filter's EKF kernels: the structured prediction while walking and while
/// standing, and the covariance downdate of the measurement updates. P is symmetric and only its
/// upper triangle (i <= j) is read and written.
#pragma once

#include <cstddef>

#include "yoyogait/gait/pair.hpp"
#include "yoyogait/gait/state.hpp"
#include "yoyogait/math.hpp"

namespace yoyogait {

/// Process noise of one prediction, already multiplied by dt (sec. 2.2). The frequency-rate noise
/// q_rate(dw_lp) dt is added by the filter after the prediction, where dw_lp is known.
struct GaitProcessNoise {
  double phasor = 0.0;  ///< q_phasor dt on each of X1, X2, Z1, Z2 [(m/s)^2]
  double phase = 0.0;   ///< q_phase dt, times g g^T [rad^2]
  double omega = 0.0;   ///< q_omega dt on w [(rad/s)^2]
  double speed = 0.0;   ///< q_speed dt on A0 [(m/s)^2]
  double accel = 0.0;   ///< q_accel dt on dA0 [(m/s^2)^2]
};

/// EKF prediction while walking: x <- f(x) (gait_transition), P <- F P F^T + Q (without the dw
/// term). P is symmetric and only its upper triangle (i <= j) is read and written.
///
/// F is never formed. With a = the phasors (X, Z), b = [w, A0, dA0, dw], F = [[Rr, g e_w^T], [0, L]]
/// (Rr = diag(Rot, Rot), g = dt gq, gq = [-X2', X1', -Z2', Z1'] at the rotated phasors), so
///   P'aa = Rr Paa Rr^T + gq u'^T + u' gq^T + q_phasor I,  u' = dt Rr P[a][w] + (dt^2 P[w][w] + q_phase) / 2 gq
///   P'ab = (Rr Pab + g P[w][b]) L^T,                        P'bb = L Pbb L^T + Q_bb.
/// Rot B Rot^T of a 2x2 block B leaves its rotation-invariant part (alpha I + beta J) alone and turns
/// its reflection part [[p, q], [q, -p]] by 2 phi: about 230 flops instead of ~1900 for the two
/// dense products of F P F^T. Lanes: the X and Z lanes' form (gait/pair.hpp), the target's SSE2
/// pairs by default; gait::ScalarPair gives the same bits.
template <class Lanes = gait::Pair>
void gait_predict(GaitState& x, GaitMatrix& P, double dt, double accel_decay, double omega_rate_decay,
                  const GaitProcessNoise& q) noexcept {
  using namespace gait;
  double s, c;
  sincos(x[kW] * dt, s, c);
  // X and Z go through the same operations: one lane each (gait/pair.hpp), the scalar form's bits.
  const Lanes pc = Lanes::splat(c), ps = Lanes::splat(s);
  const Lanes p1 = Lanes::of(x[kX1], x[kZ1]), p2 = Lanes::of(x[kX2], x[kZ2]);
  const Lanes R1 = pc * p1 - ps * p2, R2 = ps * p1 + pc * p2;  // (X1, Z1), (X2, Z2) turned
  const double X1 = R1.lo(), X2 = R2.lo(), Z1 = R1.hi(), Z2 = R2.hi();
  x[kX1] = X1;
  x[kX2] = X2;
  x[kZ1] = Z1;
  x[kZ2] = Z2;
  x[kW] += dt * x[kDW];
  x[kDW] *= omega_rate_decay;
  x[kA0] += dt * x[kDA0];
  x[kDA0] *= accel_decay;

  const double a = accel_decay, b = omega_rate_decay;
  const double g0 = -X2, g1 = X1, g2 = -Z2, g3 = Z1;  // gq: d(state)/d(phase) at the rotated phasors
  const Lanes G02 = negated(R2), G13 = R1;               // (g0, g2), (g1, g3)

  // Rotation by 2 phi of the reflection parts (cos 2phi, sin 2phi), halves folded in.
  const double C2 = 0.5 * ((c + s) * (c - s)), S2 = c * s;  // = cos(2 phi) / 2, sin(2 phi) / 2
  // XX and ZZ blocks (symmetric: no J part), as (X, Z) pairs: m = mean of the variances, h = their
  // difference and q = the covariance, h and q turned by 2 phi.
  const Lanes d1 = Lanes::of(P[kX1][kX1], P[kZ1][kZ1]), d2 = Lanes::of(P[kX2][kX2], P[kZ2][kZ2]);
  const Lanes q12 = Lanes::of(P[kX1][kX2], P[kZ1][kZ2]);
  const Lanes m12 = Lanes::splat(0.5) * (d1 + d2), h12 = d1 - d2;
  const Lanes hr12 = Lanes::splat(C2) * h12 - Lanes::splat(S2 + S2) * q12;
  const Lanes qr12 = Lanes::splat(S2) * h12 + Lanes::splat(C2 + C2) * q12;
  // XZ block (general): alpha I + beta J + [[p, q], [q, -p]].
  const double al = 0.5 * (P[kX1][kZ1] + P[kX2][kZ2]), be = 0.5 * (P[kX2][kZ1] - P[kX1][kZ2]);
  const double pXZ = P[kX1][kZ1] - P[kX2][kZ2], qXZ = P[kX1][kZ2] + P[kX2][kZ1];
  const double pr = C2 * pXZ - S2 * qXZ, qr = S2 * pXZ + C2 * qXZ;

  // V = Rr Pab + dt gq P[w][b] (4 x 4): row i the phasor entry i, column j the entry kW + j of b.
  constexpr std::size_t jW = kW - kW, jA0 = kA0 - kW, jDA0 = kDA0 - kW, jDW = kDW - kW;
  double V[kPhasors][kDim - kPhasors];
  for (std::size_t j = 0; j < kDim - kPhasors; ++j) {
    const std::size_t k = kW + j;
    const double pw = dt * P[kW][k];
    V[kX1][j] = c * P[kX1][k] - s * P[kX2][k] + g0 * pw;
    V[kX2][j] = s * P[kX1][k] + c * P[kX2][k] + g1 * pw;
    V[kZ1][j] = c * P[kZ1][k] - s * P[kZ2][k] + g2 * pw;
    V[kZ2][j] = s * P[kZ1][k] + c * P[kZ2][k] + g3 * pw;
  }
  // u' = dt Rr P[a][w] + (dt^2 Pww + q_phase) / 2 gq, from the prior P[a][w] and Pww.
  const double Pww = P[kW][kW];
  const double hw = 0.5 * (dt * dt * Pww + q.phase);
  const Lanes w1 = Lanes::of(P[kX1][kW], P[kZ1][kW]), w2 = Lanes::of(P[kX2][kW], P[kZ2][kW]);
  const Lanes U02 = Lanes::splat(dt) * (pc * w1 - ps * w2) + Lanes::splat(hw) * G02;  // (u0, u2)
  const Lanes U13 = Lanes::splat(dt) * (ps * w1 + pc * w2) + Lanes::splat(hw) * G13;  // (u1, u3)

  // P'bb = L Pbb L^T + Q_bb: w' = w + dt dw, A0' = A0 + dt dA0, dA0' = a dA0, dw' = b dw.
  // (M = L Pbb row by row; names: W = w, A = A0, D = dA0, R = dw.)
  const double mWW = P[kW][kW] + dt * P[kW][kDW], mWR = P[kW][kDW] + dt * P[kDW][kDW];
  const double mWA = P[kW][kA0] + dt * P[kA0][kDW], mWD = P[kW][kDA0] + dt * P[kDA0][kDW];
  const double mAA = P[kA0][kA0] + dt * P[kA0][kDA0], mAD = P[kA0][kDA0] + dt * P[kDA0][kDA0],
               mAR = P[kA0][kDW] + dt * P[kDA0][kDW];
  const double pWW = mWW + dt * mWR + q.omega;
  const double pWA = mWA + dt * mWD;
  const double pWD = a * mWD;
  const double pWR = b * mWR;
  const double pAA = mAA + dt * mAD + q.speed;
  const double pAD = a * mAD;
  const double pAR = b * mAR;
  const double pDD = a * a * P[kDA0][kDA0] + q.accel;
  const double pDR = a * b * P[kDA0][kDW];
  const double pRR = b * b * P[kDW][kDW];

  // Write P'aa (rotation part + symmetric rank-2 + q_phasor I).
  const Lanes two = Lanes::splat(2.0), qph = Lanes::splat(q.phasor);
  const Lanes D1 = m12 + hr12 + two * G02 * U02 + qph, D2 = m12 - hr12 + two * G13 * U13 + qph;
  const Lanes O12 = qr12 + G02 * U13 + U02 * G13;
  P[kX1][kX1] = D1.lo();
  P[kZ1][kZ1] = D1.hi();
  P[kX2][kX2] = D2.lo();
  P[kZ2][kZ2] = D2.hi();
  P[kX1][kX2] = O12.lo();
  P[kZ1][kZ2] = O12.hi();
  // XZ block, row by row: (P'[X1][Z1], P'[X1][Z2]) and (P'[X2][Z1], P'[X2][Z2]) (adjacent in P).
  static_assert(kZ2 == kZ1 + 1, "Z1, Z2 adjacent");
  const Lanes u23 = highs(U02, U13), g23 = highs(G02, G13);
  const Lanes xz1 = Lanes::of(al + pr, qr - be) + Lanes::splat(g0) * u23 + Lanes::splat(U02.lo()) * g23;
  const Lanes xz2 = Lanes::of(qr + be, al - pr) + Lanes::splat(g1) * u23 + Lanes::splat(U13.lo()) * g23;
  store2(&P[kX1][kZ1], xz1);
  store2(&P[kX2][kZ1], xz2);
  // P'ab = V L^T.
  for (std::size_t i = 0; i < kPhasors; ++i) {
    P[i][kW] = V[i][jW] + dt * V[i][jDW];
    P[i][kA0] = V[i][jA0] + dt * V[i][jDA0];
    P[i][kDA0] = a * V[i][jDA0];
    P[i][kDW] = b * V[i][jDW];
  }
  P[kW][kW] = pWW;
  P[kW][kA0] = pWA;
  P[kW][kDA0] = pWD;
  P[kW][kDW] = pWR;
  P[kA0][kA0] = pAA;
  P[kA0][kDA0] = pAD;
  P[kA0][kDW] = pAR;
  P[kDA0][kDA0] = pDD;
  P[kDA0][kDW] = pDR;
  P[kDW][kDW] = pRR;
}

namespace gait {

/// Prediction while standing: the oscillator is frozen; only A0 and dA0 evolve.
/// F = I + dt e_A0 e_dA0^T + (a - 1) e_dA0 e_dA0^T; qb, qa: the noise of A0 and dA0 (times dt).
inline void predict_standing(GaitState& x, GaitMatrix& P, double dt, double a, double qb, double qa) noexcept {
  x[kA0] += dt * x[kDA0];
  x[kDA0] *= a;
  // Rows and columns A0 and dA0; upper triangle: P[i][kA0], P[i][kDA0] for i < kA0, P[kA0][j], P[kDA0][j] for j > kDA0.
  for (std::size_t i = 0; i < kA0; ++i) {
    P[i][kA0] += dt * P[i][kDA0];
    P[i][kDA0] *= a;
  }
  P[kA0][kDW] += dt * P[kDA0][kDW];
  P[kDA0][kDW] *= a;
  const double mAA = P[kA0][kA0] + dt * P[kA0][kDA0], mAD = P[kA0][kDA0] + dt * P[kDA0][kDA0];
  P[kA0][kA0] = mAA + dt * mAD + qb;
  P[kA0][kDA0] = a * mAD;
  P[kDA0][kDA0] = a * a * P[kDA0][kDA0] + qa;
}

/// Column Col of the symmetric P (upper triangle stored): P[r][Col] for every r.
template <std::size_t Col>
void column(const GaitMatrix& P, double (&out)[kDim]) noexcept {
  for (std::size_t r = 0; r < kDim; ++r) out[r] = r <= Col ? P[r][Col] : P[Col][r];
}

/// P -= k1 ph1^T + k2 ph2^T on the upper triangle (rows from their first even column, so that
/// pairs of entries go together; the few lower entries this touches are never read).
template <std::size_t R>
void downdate_row(GaitMatrix& P, const double (&k1)[kDim], const double (&ph1)[kDim], const double (&k2)[kDim],
                  const double (&ph2)[kDim]) noexcept {
  constexpr std::size_t c0 = R & ~std::size_t{1};  // compile-time bounds: unrolled, in pairs
  const double a = k1[R], b = k2[R];
  for (std::size_t c = c0; c < kDim; ++c) P[R][c] -= a * ph1[c] + b * ph2[c];
}
inline void downdate(GaitMatrix& P, const double (&k1)[kDim], const double (&ph1)[kDim], const double (&k2)[kDim],
                     const double (&ph2)[kDim]) noexcept {
  downdate_row<kX1>(P, k1, ph1, k2, ph2);
  downdate_row<kX2>(P, k1, ph1, k2, ph2);
  downdate_row<kZ1>(P, k1, ph1, k2, ph2);
  downdate_row<kZ2>(P, k1, ph1, k2, ph2);
  downdate_row<kW>(P, k1, ph1, k2, ph2);
  downdate_row<kA0>(P, k1, ph1, k2, ph2);
  downdate_row<kDA0>(P, k1, ph1, k2, ph2);
  downdate_row<kDW>(P, k1, ph1, k2, ph2);
}

}  // namespace gait
}  // namespace yoyogait
