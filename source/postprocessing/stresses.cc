#include <deal.II/base/quadrature_lib.h>
#include <deal.II/fe/fe_values.h>

#include <feticontact/postprocessing/stresses.h>

#include <cmath>

namespace FetiContact
{
  using namespace dealii;

  std::vector<SymmetricTensor<2, 3>>
  cell_stresses(const Subdomain &subdomain, const Mapping<3> &mapping, const Vector<double> &u)
  {
    const auto                      &fe = subdomain.dof_handler.get_fe();
    FEValues<3>                      fe_values(mapping, fe, QGaussSimplex<3>(1), update_gradients);
    const double                     lambda = subdomain.body.parameters.material.lambda();
    const double                     mu     = subdomain.body.parameters.material.mu();
    const FEValuesExtractors::Vector displacement(0);
    std::vector<SymmetricTensor<2, 3>> strain(1);
    std::vector<SymmetricTensor<2, 3>> stress(subdomain.mesh.n_active_cells());
    for (const auto &cell : subdomain.dof_handler.active_cell_iterators())
      {
        fe_values.reinit(cell);
        fe_values[displacement].get_function_symmetric_gradients(u, strain);
        stress[cell->active_cell_index()] =
          lambda * trace(strain[0]) * unit_symmetric_tensor<3>() + 2 * mu * strain[0];
      }
    return stress;
  }

  double
  von_mises(const SymmetricTensor<2, 3> &sigma)
  {
    const auto s = deviator(sigma);
    return std::sqrt(1.5 * (s * s));
  }
} // namespace FetiContact
