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
                      "g = F λ_N, found by successive approximations) or 'tresca' (the given "
                      "'Slip bound').");
    prm.declare_entry("Slip bound",
                      "0",
                      Patterns::Double(0),
                      "Tresca: the slip bound g of every contact node with F > 0, a nodal force "
                      "(N).");
    prm.declare_entry("Algorithm",
                      "algorithm 2",
                      Patterns::Selection("algorithm 1|algorithm 2|mpgp|polygonal"),
                      "'algorithm 1': MSA outer loop, each step SMALBE with block Gauss–Seidel "
                      "(MPRGP on λ_N, λ_E, then KPG on the tangential discs); 'algorithm 2': the "
                      "seed's combined loop (one MPRGP and one KPG solve and one multiplier "
                      "update per iteration); 'mpgp': MSA with SMALBE and one MPGP over bounds × "
                      "discs; 'polygonal': the disc replaced by a regular 2s-gon with s "
                      "multipliers in boxes (the seed's Table 3 baseline).");
    prm.declare_entry("Polygon directions",
                      "4",
                      Patterns::Integer(2),
                      "polygonal: s, the number of tangential multipliers per node (2: square, "
                      "4: octagon).");
    prm.declare_entry("Accuracy",
                      "engineering",
                      Patterns::Selection("draft|engineering|reference"),
                      "A preset of the two relative tolerances below, chosen from the speed/"
                      "accuracy study of the brick (doc/accuracy.md; solver errors in the energy "
                      "norm measured at k = 8): 'draft' MSA = QP = 1e-3 (5e-2, for trial runs), "
                      "'engineering' MSA 1e-6, QP 1e-8 (2e-7), 'reference' MSA = QP = 1e-10 "
                      "(4e-9, for verification). Either tolerance given as a number overrides "
                      "its preset.");
    prm.declare_entry("QP relative tolerance",
                      "preset",
                      Patterns::Anything(),
                      "SMALBE stops when ‖g^P(λ)‖ ≤ tol ‖h‖ and ‖Gλ − e‖ ≤ tol ‖e‖. 'preset': "
                      "from Accuracy.");
    prm.declare_entry("MSA relative tolerance",
                      "preset",
                      Patterns::Anything(),
                      "Successive approximations stop when the slip bound changes by less than "
                      "this fraction: ‖g_new − g‖ ≤ tol ‖g_new‖. 'preset': from Accuracy.");
    prm.declare_entry("Maximum MSA iterations", "100", Patterns::Integer(1), "");
    prm.declare_entry("Inexact MSA factor",
                      "0.01",
                      Patterns::Double(0, 1),
                      "c: MSA step j solves its Tresca problem only to the relative tolerance "
                      "max(QP relative tolerance, c × the relative change of the slip bound in "
                      "step j − 1) (1 in step 1); MSA stops only after a step solved to the QP "
                      "relative tolerance. 0: every step to the QP relative tolerance.");
    prm.declare_entry("Maximum SMALBE iterations",
                      "auto",
                      Patterns::Anything(),
                      "The limit of SMALBE's outer iterations per QP solve, or 'auto': 200 for "
                      "algorithm 2 (per call of its loop, which is then repeated warm), 2000 for "
                      "the others. With a small penalty (algorithm 1: ρ = 0.1‖F‖) ‖Gλ − e‖ can "
                      "fall by only a few percent per iteration; the brick with Algorithm 1 at "
                      "F = 0.1 or 1e-8 or without contact needs 300–700 (doc/validation.md).");
    prm.declare_entry("Maximum inner iterations",
                      "10000",
                      Patterns::Integer(1),
                      "Largest number of MPRGP/MPGP iterations per inner solve.");
    prm.declare_entry("Gauss-Seidel sweeps",
                      "1",
                      Patterns::Integer(1),
                      "algorithm 1: block Gauss–Seidel sweeps (λ_c, then λ_t) per inner problem.");
    prm.declare_entry("Relaxation",
                      "1",
                      Patterns::Double(0, 1),
                      "ω in the slip-bound update g ← (1 − ω) g + ω F λ_N (1: plain MSA).");
    prm.declare_entry("Friction continuation steps",
                      "1",
                      Patterns::Integer(1),
                      "n: solve the Coulomb problem for F/n, 2F/n, …, F in turn, each stage "
                      "starting from the solution of the previous one (the intermediate stages "
                      "to 100 × the MSA tolerance). 1: no continuation.");
    prm.declare_entry("Inner tolerance floor",
                      "1",
                      Patterns::Double(0, 1),
                      "c ∈ (0, 1]: SMALBE's inner solves stop no later than at c × the final "
                      "gradient tolerance. With 1 SMALBE can stall with ‖Gλ − e‖ a few times above "
                      "its tolerance (prm/hertz.prm: a body held only by frictionless contact); "
                      "0.1 avoids that at the price of more precise inner solves.");
    prm.declare_entry("Penalty factor",
                      "auto",
                      Patterns::Anything(),
                      "SMALBE's penalty ρ as a multiple of the estimated ‖F‖ (or ‖PFP‖, Penalty "
                      "norm), or 'auto': 1 for mpgp and polygonal (3 with Penalty norm = "
                      "projected F), 0.1 for algorithm 1, 0.03 for algorithm 2. The block "
                      "Gauss–Seidel of algorithms 1 and 2 converges slowly when ρG̃ᵀG̃ couples "
                      "λ_c and λ_T strongly (measured on the brick, doc/contact.md).");
    prm.declare_entry("Multiplier step factor",
                      "1",
                      Patterns::Double(0, 2),
                      "s ∈ (0, 2) in SMALBE's multiplier update μ ← μ + sρ(Gλ − e). 1 (the "
                      "default) is SMALBE as published. s > 1 over-relaxes the update: on the "
                      "brick with the six options of doc/performance.md, s = 1.5 makes 22 % fewer "
                      "Hessian multiplications at 10⁶ unknowns (k = 48: 687 against 878), where "
                      "many outer iterations each reduce ‖Gλ − e‖ by a few percent only, and "
                      "13–18 % more at k = 8 and 16.");
    prm.declare_entry(
      "Penalty norm",
      "F",
      Patterns::Selection("F|projected F"),
      "The norm that Penalty factor multiplies, and that bounds the FETI part of the Hessian "
      "in MPGP's fixed step: 'F' the estimated ‖F‖; 'projected F' the estimated ‖PFP‖ "
      "(Equality constraint = projector, Algorithm = mpgp or polygonal). With floating "
      "subdomains ‖F‖ includes the action of the local pseudo-inverses on the rigid body "
      "modes, which P removes: on the brick (TFETI, H/h = 8) ‖F‖ is about 70 ‖PFP‖, so the "
      "penalty ρ = ‖F‖ puts the eigenvalue ρ of the Hessian PFP + ρQ 70 times above the rest "
      "of its spectrum, and every face of the constraints mixes the two. 'auto' Penalty "
      "factor with 'projected F': 3. Measured in doc/performance.md.");
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
    prm.declare_entry(
      "Expansion step",
      "fixed",
      Patterns::Selection("fixed|projected cg"),
      "How MPGP/MPRGP activates constraints when a conjugate gradient step "
      "leaves the feasible set: 'fixed' (Dostál–Schöberl: the feasible half step, "
      "then the projected step of fixed length ᾱ = 1.9/‖A‖; activates about one "
      "contact node per expansion) or 'projected cg' (the whole conjugate "
      "gradient step projected onto the feasible set, kept if the energy "
      "decreased, else the fixed step; Kružík et al. 2020, PERMON's projcg). Measured in "
      "doc/performance.md.");
    prm.declare_entry(
      "Hessian norm bound",
      "sum",
      Patterns::Selection("sum|max"),
      "The bound of ‖A‖ behind MPGP's fixed step ᾱ = 1.9/‖A‖ (expansion and projected "
      "gradient steps): 'sum' ‖F‖ + ρ, valid for either equality constraint; 'max' "
      "max(‖F‖, ρ), valid only for the projector variant, whose Hessian PFP + ρQ acts on "
      "the complementary orthogonal subspaces ker G̃ and range G̃ᵀ (with the penalty "
      "ρ = ‖F‖ of 'mpgp' it doubles ᾱ). Measured in doc/performance.md.");
    prm.declare_entry(
      "Recursive gradient tolerance",
      "0",
      Patterns::Double(0),
      "MPGP: η of the recursive gradient update after a step that the projection onto the "
      "feasible set moved off its line (conjugate gradient steps along the circles of "
      "slipping nodes, projected CG expansions). 0: the gradient is recomputed after every "
      "such step (two multiplications per step). η > 0: it is updated as g − αAp, leaving "
      "out A times the return onto the feasible set, as long as the bound of the error, "
      "(2/ᾱ) × the summed returns, stays below η‖g^P‖; every stopping decision is made on a "
      "recomputed gradient. Measured in doc/performance.md.");
    prm.declare_entry(
      "Arc preconditioner scale",
      "norm",
      Patterns::Selection("norm|mean diagonal"),
      "MPGP with Disc rotations: the conjugate gradient steps along the circles of slipping "
      "nodes are preconditioned by 1/(1 + σ/(r a)) (σ the force pressing a node's tangential "
      "multiplier outwards, r the slip bound), a the scale of the Hessian A: 'norm' its norm "
      "bound (that of the fixed step), 'mean diagonal' tr(A)/m, estimated once from 10 "
      "multiplications by F (Hutchinson). The latter is the Jacobi scaling along the circles; "
      "on the brick (H/h = 8) ‖A‖ is 71–98 times the mean diagonal. Measured in "
      "doc/performance.md.");
    prm.declare_entry(
      "Preconditioner",
      "none",
      Patterns::Selection("none|lumped"),
      "Preconditioning in face of MPGP's conjugate gradient steps (Algorithm = mpgp or "
      "polygonal): 'none', or 'lumped': the lumped FETI preconditioner D B K Bᵀ D "
      "(D = diag(B Bᵀ)⁻¹), projected, P M P + Q/ρ, restricted to the free set. One sparse "
      "multiplication by every K_i per step, no solve. Measured in doc/performance.md.");
    prm.leave_subsection();
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
    polygon_directions  = prm.get_integer("Polygon directions");
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
    msa_tolerance         = tolerance("MSA relative tolerance", preset[0]);
    qp_tolerance          = tolerance("QP relative tolerance", preset[1]);
    max_msa_iterations    = prm.get_integer("Maximum MSA iterations");
    inexact_msa_factor    = prm.get_double("Inexact MSA factor");
    inner_tolerance_floor = prm.get_double("Inner tolerance floor");
    multiplier_step       = prm.get_double("Multiplier step factor");
    require(multiplier_step > 0 && multiplier_step < 2,
            "Contact solver/Multiplier step factor must lie in (0, 2) (the method of "
            "multipliers diverges from 2 on); got " +
              prm.get("Multiplier step factor") + ".");
    require(inner_tolerance_floor > 0,
            "Contact solver/Inner tolerance floor must lie in (0, 1]; got 0.");
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
    max_inner_iterations = prm.get_integer("Maximum inner iterations");
    gauss_seidel_sweeps  = prm.get_integer("Gauss-Seidel sweeps");
    relaxation           = prm.get_double("Relaxation");
    continuation_steps   = prm.get_integer("Friction continuation steps");
    require(relaxation > 0, "Contact solver/Relaxation must be in (0, 1]; got 0.");
    const std::string penalty = prm.get("Penalty factor");
    if (penalty == "auto")
      penalty_factor = algorithm == Algorithm::algorithm_1 ? 0.1 :
                       algorithm == Algorithm::algorithm_2 ? 0.03 :
                                                             1.0;
    else
      {
        penalty_factor = InputParsing::parse_double(penalty, "Contact solver/Penalty factor");
        require(penalty_factor > 0 && std::isfinite(penalty_factor),
                "Contact solver/Penalty factor must be 'auto' or a positive number; got '" +
                  penalty + "'.");
      }
    equality_constraint    = prm.get("Equality constraint") == "projector" ?
                               EqualityConstraint::projector :
                               EqualityConstraint::penalty;
    disc_rotations         = prm.get_bool("Disc rotations");
    const std::string step = prm.get("Expansion step");
    expansion              = step == "projected cg" ? QP::MpgpOptions::Expansion::projected_cg :
                                                      QP::MpgpOptions::Expansion::fixed_step;
    penalty_projected_norm = prm.get("Penalty norm") == "projected F";
    require(!penalty_projected_norm || equality_constraint == EqualityConstraint::projector,
            "Contact solver/Penalty norm = projected F needs Equality constraint = projector "
            "(‖PFP‖ bounds the Hessian only when P projects it).");
    require(!penalty_projected_norm ||
              (algorithm == Algorithm::mpgp || algorithm == Algorithm::polygonal),
            "Contact solver/Penalty norm = projected F is implemented for Algorithm = mpgp and "
            "polygonal only (the penalties of algorithms 1 and 2 are tuned against ‖F‖).");
    if (penalty_projected_norm && penalty == "auto")
      penalty_factor = 3.0;
    hessian_norm_max = prm.get("Hessian norm bound") == "max";
    require(!hessian_norm_max || equality_constraint == EqualityConstraint::projector,
            "Contact solver/Hessian norm bound = max holds only with Equality constraint = "
            "projector (the Hessian F + ρG̃ᵀG̃ of the penalty variant is bounded by the sum).");
    recursive_gradient_tolerance = prm.get_double("Recursive gradient tolerance");
    arc_scale_mean_diagonal      = prm.get("Arc preconditioner scale") == "mean diagonal";
    lumped_preconditioner        = prm.get("Preconditioner") == "lumped";
    require(!lumped_preconditioner ||
              (algorithm == Algorithm::mpgp || algorithm == Algorithm::polygonal),
            "Contact solver/Preconditioner = lumped is implemented for Algorithm = mpgp and "
            "polygonal only (algorithms 1 and 2 solve blocks of λ by Gauss–Seidel).");
    prm.leave_subsection();
  }
} // namespace FetiContact::Parameters
