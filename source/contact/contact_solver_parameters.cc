#include <feticontact/base/input_parsing.h>
#include <feticontact/contact/contact_solver_parameters.h>

#include <array>
#include <cmath>

namespace FetiContact::Parameters
{
  using namespace dealii;

  void
  ContactSolver::declare_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Contact solver");
    prm.declare_entry("Friction law",
                      "coulomb",
                      Patterns::Selection("coulomb|tresca"),
                      "For zones with a friction coefficient F > 0: 'coulomb' (slip bound "
                      "g = F λ_N, the fixed point found by successive approximations, MSA) or "
                      "'tresca' (the given 'Slip bound').");
    prm.declare_entry("Slip bound",
                      "0",
                      Patterns::Double(0),
                      "Tresca: the slip bound g of every contact node with F > 0, a nodal force "
                      "(N).");
    prm.declare_entry("Algorithm",
                      "mpgp",
                      Patterns::Selection("mpgp|algorithm 1|algorithm 2|polygonal"),
                      "'mpgp': MSA outer loop, each step one MPGP over bounds × discs inside "
                      "SMALBE with the projector. The seed paper's algorithms, for reproducing "
                      "its tables: 'algorithm 1' (MSA outer loop, SMALBE with block Gauss–Seidel: "
                      "MPRGP on λ_N, λ_E, then KPG on the tangential discs); 'algorithm 2' (MSA "
                      "and the augmented Lagrangian merged in one loop: one MPRGP and one KPG "
                      "solve and one multiplier update per iteration); 'polygonal' (the disc "
                      "replaced by a regular 2s-gon with s multipliers in boxes, MPRGP only).");
    prm.declare_entry("Accuracy",
                      "engineering",
                      Patterns::Selection("draft|engineering|reference"),
                      "A preset of the two relative tolerances below: 'draft' MSA = QP = 1e-3 "
                      "(trial runs), 'engineering' MSA 1e-6, QP 1e-8, 'reference' MSA = QP = "
                      "1e-10 (verification). Either tolerance given as a number overrides its "
                      "preset.");
    prm.declare_entry("QP relative tolerance",
                      "preset",
                      Patterns::Anything(),
                      "A number in (0, 1) or 'preset' (from Accuracy): SMALBE stops when "
                      "‖g^P(λ)‖ ≤ tol ‖h‖ and ‖Gλ − e‖ ≤ tol ‖e‖.");
    prm.declare_entry("MSA relative tolerance",
                      "preset",
                      Patterns::Anything(),
                      "A number in (0, 1) or 'preset' (from Accuracy): successive approximations "
                      "stop when the slip bound changes by less than this fraction, "
                      "‖g_new − g‖ ≤ tol ‖g_new‖.");
    prm.declare_entry("Maximum MSA iterations",
                      "100",
                      Patterns::Integer(1),
                      "The limit of the successive approximations of the slip bound.");
    prm.declare_entry("Maximum SMALBE iterations",
                      "auto",
                      Patterns::Anything(),
                      "A positive integer, the limit of SMALBE's outer iterations per QP solve, "
                      "or 'auto': 200 for algorithm 2 (per call of its loop, which is then "
                      "repeated warm), 2000 for the others.");
    prm.enter_subsection("Expert");
    declare_expert_parameters(prm);
    prm.leave_subsection();
    prm.leave_subsection();
  }

  void
  ContactSolver::declare_expert_parameters(ParameterHandler &prm)
  {
    prm.declare_entry("Polygon directions",
                      "4",
                      Patterns::Integer(2),
                      "polygonal: s, the number of tangential multipliers per node (2: square, "
                      "4: octagon).");
    prm.declare_entry("Maximum inner iterations",
                      "10000",
                      Patterns::Integer(1),
                      "The limit of MPRGP/MPGP iterations per inner solve of SMALBE.");
    prm.declare_entry("Inexact MSA factor",
                      "auto",
                      Patterns::Anything(),
                      "A number c in [0, 1) or 'auto' (0.001 for mpgp, 0.01 otherwise): MSA step "
                      "j solves its Tresca problem only to the relative tolerance max(QP relative "
                      "tolerance, c × the relative change of the slip bound in step j − 1) (1 in "
                      "step 1); MSA stops only after a step solved to the QP relative tolerance. "
                      "0: every step to the QP relative tolerance.");
    prm.declare_entry("Inner tolerance floor",
                      "1",
                      Patterns::Double(0, 1),
                      "c ∈ (0, 1]: SMALBE's inner solves stop no later than at c × the final "
                      "gradient tolerance. Below 1 the inner solves are more precise than SMALBE "
                      "needs, which can help a body held only by frictionless contact, where "
                      "‖Gλ − e‖ may otherwise stall a few times above its tolerance.");
    prm.declare_entry("Gauss-Seidel sweeps",
                      "1",
                      Patterns::Integer(1),
                      "algorithm 1: block Gauss–Seidel sweeps (λ_c, then λ_t) per inner problem.");
    prm.declare_entry("Relaxation",
                      "1",
                      Patterns::Double(0, 1),
                      "ω ∈ (0, 1] in the slip-bound update g ← (1 − ω) g + ω F λ_N (1: plain "
                      "MSA); below 1 for large friction coefficients, where MSA may oscillate.");
    prm.declare_entry("Friction continuation steps",
                      "1",
                      Patterns::Integer(1),
                      "n: solve the Coulomb problem for F/n, 2F/n, …, F in turn, each stage "
                      "starting from the solution of the previous one (the intermediate stages "
                      "to 100 × the MSA tolerance). 1: no continuation.");
    prm.declare_entry(
      "Penalty factor",
      "auto",
      Patterns::Anything(),
      "SMALBE's penalty ρ as a multiple of the estimated norm of the FETI part of "
      "the Hessian (‖PFP‖ for mpgp with the projector, ‖F‖ otherwise), or 'auto': "
      "5 for mpgp, 1 for polygonal, 0.1 for algorithm 1, 0.03 for algorithm 2. The block Gauss–Seidel of algorithms 1 "
      "and 2 converges slowly when ρG̃ᵀG̃ couples λ_c and λ_T strongly.");
    prm.declare_entry("Multiplier step factor",
                      "1",
                      Patterns::Double(0, 2),
                      "s ∈ (0, 2) in SMALBE's multiplier update μ ← μ + sρ(Gλ − e); 1 is SMALBE "
                      "as published, s > 1 over-relaxes the update.");
    prm.declare_entry("Equality constraint",
                      "projector",
                      Patterns::Selection("projector|penalty"),
                      "How SMALBE enforces Gλ = e (the equilibrium of floating subdomains): "
                      "'projector': λ = λ₀ + λ̃ with the least-norm Gλ₀ = e, the Hessian "
                      "PFP + ρQ of Farhat–Mandel–Roux (the natural coarse space); 'penalty': the "
                      "Hessian F + ρG̃ᵀG̃ with G̃ the orthonormalized G.");
    prm.declare_entry("Disc rotations",
                      "true",
                      Patterns::Bool(),
                      "MPGP/KPG on the tangential discs: conjugate gradient steps also move "
                      "active discs along their circles (true), or only proportioning steps do, "
                      "as in Dostál–Kozubek and Kučera's KPG (false; much slower when most "
                      "nodes slip).");
    prm.declare_entry("Expansion step",
                      "auto",
                      Patterns::Selection("auto|fixed|projected cg"),
                      "How MPGP/MPRGP activates constraints when a conjugate gradient step leaves "
                      "the feasible set: 'fixed' (Dostál–Schöberl: the feasible half step, then "
                      "the projected step of fixed length ᾱ = 1.9/‖A‖, which activates about one "
                      "constraint per expansion) or 'projected cg' (the whole conjugate gradient "
                      "step projected onto the feasible set, kept if the energy decreased, else "
                      "the fixed step; Kružík et al. 2020). 'auto': projected cg for mpgp, fixed "
                      "otherwise.");
    prm.declare_entry("Hessian norm bound",
                      "auto",
                      Patterns::Selection("auto|sum|max"),
                      "The bound of ‖A‖ behind MPGP's fixed step ᾱ = 1.9/‖A‖: 'sum' ‖F‖ + ρ, "
                      "valid for either equality constraint; 'max' max(‖F‖, ρ), valid only for "
                      "the projector, whose Hessian PFP + ρQ acts on the complementary orthogonal "
                      "subspaces ker G̃ and range G̃ᵀ. 'auto': max for mpgp, sum otherwise.");
    prm.declare_entry("Recursive gradient tolerance",
                      "auto",
                      Patterns::Anything(),
                      "A number η ≥ 0 or 'auto' (0.1 for mpgp, 0 otherwise). After a step that "
                      "the projection onto the feasible set moved off its line (conjugate "
                      "gradient steps along the circles of slipping nodes, projected CG "
                      "expansions), MPGP updates the gradient as g − αAp, leaving out A times the "
                      "return onto the feasible set, as long as the bound of the error, (2/ᾱ) × "
                      "the summed returns, stays below η‖g^P‖; every stopping decision is made on "
                      "a recomputed gradient. 0: recompute after every such step.");
    prm.declare_entry("Arc preconditioner scale",
                      "auto",
                      Patterns::Selection("auto|norm|mean diagonal"),
                      "MPGP with Disc rotations: the conjugate gradient steps along the circles of "
                      "slipping nodes are preconditioned by 1/(1 + σ/(r a)) (σ the force pressing "
                      "a node's tangential multiplier outwards, r the slip bound), a the scale of "
                      "the Hessian A: 'norm' its norm bound, 'mean diagonal' tr(A)/m, estimated "
                      "once from 10 multiplications (Hutchinson), the Jacobi scaling along the "
                      "circles. 'auto': mean diagonal for mpgp, norm otherwise.");
  }

  void
  ContactSolver::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Contact solver");
    friction_law =
      prm.get("Friction law") == "coulomb" ? FrictionLaw::coulomb : FrictionLaw::tresca;
    slip_bound          = prm.get_double("Slip bound");
    const std::string a = prm.get("Algorithm");
    algorithm           = a == "algorithm 1" ? Algorithm::algorithm_1 :
                          a == "algorithm 2" ? Algorithm::algorithm_2 :
                          a == "mpgp"        ? Algorithm::mpgp :
                                               Algorithm::polygonal;
    // The presets of Accuracy: {MSA, QP} relative tolerances.
    const std::string accuracy  = prm.get("Accuracy");
    const auto        preset    = accuracy == "draft"     ? std::array<double, 2>{{1e-3, 1e-3}} :
                                  accuracy == "reference" ? std::array<double, 2>{{1e-10, 1e-10}} :
                                                            std::array<double, 2>{{1e-6, 1e-8}};
    const auto        tolerance = [&](const std::string &entry, const double preset_value) {
      const std::string text = InputParsing::trim(prm.get(entry));
      if (text == "preset")
        return preset_value;
      const double value = InputParsing::parse_double(text, "Contact solver/" + entry);
      require(value > 0 && value < 1,
              "Contact solver/" + entry + " must be 'preset' or a number in (0, 1); got '" + text +
                "'.");
      return value;
    };
    msa_tolerance                  = tolerance("MSA relative tolerance", preset[0]);
    qp_tolerance                   = tolerance("QP relative tolerance", preset[1]);
    max_msa_iterations             = prm.get_integer("Maximum MSA iterations");
    const std::string smalbe_limit = InputParsing::trim(prm.get("Maximum SMALBE iterations"));
    if (smalbe_limit == "auto")
      max_smalbe_iterations = algorithm == Algorithm::algorithm_2 ? 200 : 2000;
    else
      {
        const double limit =
          InputParsing::parse_double(smalbe_limit, "Contact solver/Maximum SMALBE iterations");
        require(limit >= 1 && limit == std::floor(limit) && limit <= 1e9,
                "Contact solver/Maximum SMALBE iterations must be 'auto' or a positive integer; "
                "got '" +
                  smalbe_limit + "'.");
        max_smalbe_iterations = static_cast<unsigned int>(limit);
      }
    prm.enter_subsection("Expert");
    parse_expert_parameters(prm);
    prm.leave_subsection();
    prm.leave_subsection();
  }

  void
  ContactSolver::parse_expert_parameters(ParameterHandler &prm)
  {
    const std::string path = "Contact solver/Expert/";
    const bool        mpgp = algorithm == Algorithm::mpgp;
    // An entry that is 'auto' or a number (of at least @p lower).
    const auto auto_or_number = [&](const std::string &entry,
                                    const double       automatic,
                                    const double       lower,
                                    const std::string &range) {
      const std::string text = InputParsing::trim(prm.get(entry));
      if (text == "auto")
        return automatic;
      const double value = InputParsing::parse_double(text, path + entry);
      require(value >= lower && std::isfinite(value),
              path + entry + " must be 'auto' or a number " + range + "; got '" + text + "'.");
      return value;
    };
    // A selection with 'auto': whether it is @p choice, or (auto) whether the algorithm is mpgp.
    const auto chosen = [&](const std::string &entry, const std::string &choice) {
      const std::string value = prm.get(entry);
      return value == "auto" ? mpgp : value == choice;
    };

    polygon_directions   = prm.get_integer("Polygon directions");
    max_inner_iterations = prm.get_integer("Maximum inner iterations");
    inexact_msa_factor   = auto_or_number("Inexact MSA factor", mpgp ? 1e-3 : 1e-2, 0, "in [0, 1)");
    require(inexact_msa_factor < 1,
            path + "Inexact MSA factor must lie in [0, 1); got " + prm.get("Inexact MSA factor") +
              ".");
    inner_tolerance_floor = prm.get_double("Inner tolerance floor");
    require(inner_tolerance_floor > 0, path + "Inner tolerance floor must lie in (0, 1]; got 0.");
    gauss_seidel_sweeps = prm.get_integer("Gauss-Seidel sweeps");
    relaxation          = prm.get_double("Relaxation");
    require(relaxation > 0, path + "Relaxation must be in (0, 1]; got 0.");
    continuation_steps = prm.get_integer("Friction continuation steps");
    multiplier_step    = prm.get_double("Multiplier step factor");
    require(multiplier_step > 0 && multiplier_step < 2,
            path +
              "Multiplier step factor must lie in (0, 2) (the method of multipliers diverges "
              "from 2 on); got " +
              prm.get("Multiplier step factor") + ".");
    equality_constraint  = prm.get("Equality constraint") == "projector" ?
                             EqualityConstraint::projector :
                             EqualityConstraint::penalty;
    const bool projector = equality_constraint == EqualityConstraint::projector;
    disc_rotations       = prm.get_bool("Disc rotations");

    // MPGP's penalty is a multiple of ‖PFP‖, the norm of the FETI part of its Hessian; the
    // seed's algorithms and the polygonal baseline keep theirs against ‖F‖.
    penalty_projected_norm = mpgp && projector;
    penalty_factor         = auto_or_number("Penalty factor",
                                    penalty_projected_norm              ? 5.0 :
                                            algorithm == Algorithm::algorithm_1 ? 0.1 :
                                            algorithm == Algorithm::algorithm_2 ? 0.03 :
                                                                                  1.0,
                                    0,
                                    "above 0");
    require(penalty_factor > 0, path + "Penalty factor must be 'auto' or a positive number.");

    expansion               = chosen("Expansion step", "projected cg") ?
                                QP::MPGP::AdditionalData::Expansion::projected_cg :
                                QP::MPGP::AdditionalData::Expansion::fixed_step;
    const bool explicit_max = prm.get("Hessian norm bound") == "max";
    hessian_norm_max        = chosen("Hessian norm bound", "max") && projector;
    require(!explicit_max || projector,
            path + "Hessian norm bound = max holds only with Equality constraint = projector (the "
                   "Hessian F + ρG̃ᵀG̃ of the penalty variant is bounded by the sum).");
    recursive_gradient_tolerance =
      auto_or_number("Recursive gradient tolerance", mpgp ? 0.1 : 0, 0, "of at least 0");
    arc_scale_mean_diagonal = chosen("Arc preconditioner scale", "mean diagonal");
  }
} // namespace FetiContact::Parameters
