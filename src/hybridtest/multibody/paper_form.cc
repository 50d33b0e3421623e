// See paper_form.h.
#include "hybridtest/multibody/paper_form.h"

namespace hybridtest::multibody {

PaperForm PaperFormFromKane(const Data<double>& data) {
  const int n = data.n;
  PaperForm form;
  // M_paper = blockdiag(I_n, −M)   (2n × 2n)
  form.M.setZero(2 * n, 2 * n);
  form.M.topLeftCorner(n, n).setIdentity();
  form.M.bottomRightCorner(n, n) = -data.M;
  // g_paper = [−W u; g_K]   (2n)
  form.g.resize(2 * n);
  form.g.head(n) = -(data.W * data.u);
  form.g.tail(n) = data.g;
  return form;
}

}  // namespace hybridtest::multibody
