#include <deal.II/base/mpi.h>
#include <deal.II/numerics/data_out.h>
#include <deal.II/numerics/data_postprocessor.h>

#include <feticontact/base/subdomain_threads.h>
#include <feticontact/postprocessing/solution_output.h>
#include <feticontact/postprocessing/stresses.h>

#include <cstdio>
#include <fstream>
#include <sstream>

namespace FetiContact
{
  using namespace dealii;

  namespace
  {
    /**
     * The Cauchy stress σ = λ tr(ε) I + 2μ ε as a tensor field for DataOut, from the gradients
     * of the displacement (constant per cell for P1, so the output is the exact cell stress).
     */
    class StressPostprocessor : public DataPostprocessorTensor<3>
    {
    public:
      StressPostprocessor(const double lambda, const double mu)
        : DataPostprocessorTensor<3>("stress", update_gradients)
        , lambda(lambda)
        , mu(mu)
      {}

      void
      evaluate_vector_field(const DataPostprocessorInputs::Vector<3> &input,
                            std::vector<Vector<double>>              &computed) const override
      {
        for (unsigned int q = 0; q < input.solution_gradients.size(); ++q)
          {
            Tensor<2, 3> grad;
            for (unsigned int c = 0; c < 3; ++c)
              grad[c] = input.solution_gradients[q][c];
            const SymmetricTensor<2, 3> eps = symmetrize(grad);
            const SymmetricTensor<2, 3> sigma =
              lambda * trace(eps) * unit_symmetric_tensor<3>() + 2 * mu * eps;
            for (unsigned int a = 0; a < 3; ++a)
              for (unsigned int b = 0; b < 3; ++b)
                computed[q][Tensor<2, 3>::component_to_unrolled_index(TableIndices<2>(a, b))] =
                  sigma[a][b];
          }
      }

    private:
      const double lambda, mu;
    };

    std::string
    piece_name(const unsigned int s)
    {
      char name[64];
      std::snprintf(name, sizeof(name), "solution_%04u.vtu", s);
      return name;
    }
  } // namespace

  void
  write_solution_vtu(ResultFiles                       &files,
                     const MPI_Comm                     comm,
                     const std::vector<Subdomain *>    &owned,
                     const std::vector<Vector<double>> &u,
                     const unsigned int                 n_subdomains,
                     const Mapping<3>                  &mapping,
                     const std::string                 &directory)
  {
    const std::vector<std::string> displacement_names(3, "displacement");
    const std::vector<DataComponentInterpretation::DataComponentInterpretation> interpretation(
      3, DataComponentInterpretation::component_is_part_of_vector);

    // The pieces are built and encoded on the subdomain threads, one subdomain per call, and
    // written in order afterwards; the pvtu record takes the list of fields from the first piece.
    const bool               rank_0 = Utilities::MPI::this_mpi_process(comm) == 0;
    std::vector<std::string> encoded(owned.size());
    std::string              record;
    SubdomainThreads::for_each(owned.size(), [&](const unsigned int i) {
      const Subdomain   &s       = *owned[i];
      const unsigned int n_cells = s.mesh.n_active_cells();
      const auto         sigma   = cell_stresses(s, mapping, u[i]);
      Vector<double>     mises(n_cells), subdomain_id(n_cells), body_id(n_cells);
      for (unsigned int c = 0; c < n_cells; ++c)
        {
          mises[c]        = von_mises(sigma[c]);
          subdomain_id[c] = s.global_index;
          body_id[c]      = s.body.index + 1;
        }
      DataOut<3> data_out;
      data_out.attach_dof_handler(s.dof_handler);
      data_out.add_data_vector(u[i], displacement_names, DataOut<3>::type_dof_data, interpretation);
      const StressPostprocessor stress(s.body.parameters.material.lambda(),
                                       s.body.parameters.material.mu());
      data_out.add_data_vector(u[i], stress);
      data_out.add_data_vector(mises, "von_mises", DataOut<3>::type_cell_data);
      data_out.add_data_vector(subdomain_id, "subdomain", DataOut<3>::type_cell_data);
      data_out.add_data_vector(body_id, "body", DataOut<3>::type_cell_data);
      data_out.build_patches(mapping);
      // zlib's fastest level: deal.II's default, best_compression, makes the files about 6 %
      // smaller and takes most of the time of the output.
      DataOutBase::VtkFlags flags;
      flags.compression_level = DataOutBase::VtkFlags::best_speed;
      data_out.set_flags(flags);
      std::ostringstream piece;
      data_out.write_vtu(piece);
      encoded[i] = piece.str();
      if (i == 0 && rank_0)
        {
          std::vector<std::string> pieces;
          for (unsigned int p = 0; p < n_subdomains; ++p)
            pieces.push_back(piece_name(p));
          std::ostringstream out;
          data_out.write_pvtu_record(out, pieces);
          record = out.str();
        }
    });
    for (unsigned int i = 0; i < owned.size(); ++i)
      files.write(directory + "/" + piece_name(owned[i]->global_index),
                  [&](std::ostream &out) { out << encoded[i]; });
    if (rank_0 && !owned.empty())
      {
        files.write(directory + "/solution.pvtu", [&](std::ostream &out) { out << record; });
        files.write(directory + "/solution.pvd", [](std::ostream &out) {
          DataOutBase::write_pvd_record(out, {{0.0, "solution.pvtu"}});
        });
      }
  }
} // namespace FetiContact
