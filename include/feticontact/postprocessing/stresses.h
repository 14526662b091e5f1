#pragma once

#include <deal.II/base/symmetric_tensor.h>
#include <deal.II/fe/mapping.h>
#include <deal.II/lac/vector.h>

#include <feticontact/subdomain/subdomain.h>

#include <vector>

namespace FetiContact
{
  /** The strain ε = sym ∇u of every cell of a subdomain (constant per cell for P1 elements). */
  std::vector<dealii::SymmetricTensor<2, 3>>
  cell_strains(const Subdomain              &subdomain,
               const dealii::Mapping<3>     &mapping,
               const dealii::Vector<double> &u);

  /**
   * The Cauchy stress σ = λ tr(ε) I + 2μ ε of every cell of a subdomain (constant per cell for
   * P1 elements), by active cell index.
   */
  std::vector<dealii::SymmetricTensor<2, 3>>
  cell_stresses(const Subdomain              &subdomain,
                const dealii::Mapping<3>     &mapping,
                const dealii::Vector<double> &u);

  /** The von Mises equivalent stress √(3/2 s:s), s the deviator of σ. */
  double
  von_mises(const dealii::SymmetricTensor<2, 3> &sigma);
} // namespace FetiContact
