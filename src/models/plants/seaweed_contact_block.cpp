#include "models/plants/seaweed_contact_block.hpp"

#include <cmath>

namespace biota::models::plants {

void evaluate_contact_block(const SphereHot* hot, const std::uint32_t* a, const std::uint32_t* b,
                            const ContactLaw& law, ContactBlockOut& out) {
  constexpr int B = kContactBlock;
  // The lanes' inputs first (indexed loads), then the law on whole lanes.
  Real xi[3][B], vi[3][B], wi[3][B], ri[B], xj[3][B], vj[3][B], wj[3][B], rj[B];
  for (int l = 0; l < B; ++l) {
    const SphereHot &p = hot[a[l]], &q = hot[b[l]];
    xi[0][l] = p.x.x, xi[1][l] = p.x.y, xi[2][l] = p.x.z;
    vi[0][l] = p.v.x, vi[1][l] = p.v.y, vi[2][l] = p.v.z;
    wi[0][l] = p.w.x, wi[1][l] = p.w.y, wi[2][l] = p.w.z;
    xj[0][l] = q.x.x, xj[1][l] = q.x.y, xj[2][l] = q.x.z;
    vj[0][l] = q.v.x, vj[1][l] = q.v.y, vj[2][l] = q.v.z;
    wj[0][l] = q.w.x, wj[1][l] = q.w.y, wj[2][l] = q.w.z;
    ri[l] = p.r, rj[l] = q.r;
  }
  // The law on whole lanes; a lane that does not touch computes on and is zeroed at the end
  // (its NaNs or infinities stay in that lane).
  for (int l = 0; l < B; ++l) {
    bool touch;
    Vec3 F, t0, t1;
    contact_law({xi[0][l], xi[1][l], xi[2][l]}, {vi[0][l], vi[1][l], vi[2][l]},
                {wi[0][l], wi[1][l], wi[2][l]}, ri[l], {xj[0][l], xj[1][l], xj[2][l]},
                {vj[0][l], vj[1][l], vj[2][l]}, {wj[0][l], wj[1][l], wj[2][l]}, rj[l], law, touch,
                F, t0, t1);
    out.fx[l] = touch ? F.x : 0.0, out.fy[l] = touch ? F.y : 0.0, out.fz[l] = touch ? F.z : 0.0;
    out.tax[l] = touch ? t0.x : 0.0, out.tay[l] = touch ? t0.y : 0.0;
    out.taz[l] = touch ? t0.z : 0.0;
    out.tbx[l] = touch ? t1.x : 0.0, out.tby[l] = touch ? t1.y : 0.0;
    out.tbz[l] = touch ? t1.z : 0.0;
  }
}

}  // namespace biota::models::plants
