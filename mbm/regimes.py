"""Long-horizon regimes: once a run reaches its attractor, the closed form of the rest.

Implemented: the LOCKED regime (β > 0, |γ| < ω²), a run settling on a stable
equilibrium θ* = d + 2πk, d = arcsin(γ/ω²).  The window loop (:func:`mbm.loop._run`)
asks :func:`locked_bound` before each window; when the bound on the neglected
nonlinearity over the whole rest of the horizon is within the tolerance, the run
takes one last "window" to ``t_bound`` whose formula is the linearized motion
(:func:`locked_eval`), so the run costs its transient only.  The RUNNING cycle (R1–R3),
the conservative LIBRATION (C1–C4) and, for a driven run, the PHASE-LOCKED orbit of the
stroboscopic map (S1–S7, a Shapiro step, integer or fractional) end the same way: the
rest is one stored period re-taken from an anchor.

Derivation (the comments below cite these items)
-------------------------------------------------

(L1) Linearization.  With θ = θ* + x and ω² sin θ* = γ,

    x'' + βx' + ω_l² x = −ω² r(x),   ω_l² = ω² cos d = sqrt(ω⁴ − γ²),
    r(x) = sin(θ* + x) − sin θ* − cos θ* · x.

By Taylor's theorem with the Lagrange remainder, r(x) = −sin d · x²/2 − cos(θ*+ξ) x³/6,
so |r(x)| ≤ ρ(|x|), ρ(A) = |sin d| A²/2 + A³/6.

(L2) Closed form of the linear part, from x(0) = x₀, x'(0) = v₀: with
s² = ω_l² − β²/4 (the sign tells the damping), b = v₀ + βx₀/2, E = e^{−βt/2},

    x_lin = x₀ E·C(t) + b E·S(t),
    x_lin' = x₀ (−β/2 E·C − s² E·S) + b (E·C − β/2 E·S),

where C = cos(st), S = sin(st)/s (under-damped, s² > 0); C = cosh(μt), S = sinh(μt)/μ,
μ² = −s² (over-damped); C = 1, S = t (critical).  (C' = −s² S, S' = C in every case.)
Over-damped, E·C and E·S are formed from λ₁ = −β/2 + μ = −ω_l²/(β/2 + μ) (no
cancellation) as E·C = (e^{λ₁t} + e^{λ₂t})/2 and E·S = e^{λ₁t}·(−expm1(−2μt))/(2μ), which
neither overflow nor cancel near critical damping.

(L3) Trapping and amplitude.  H = x'²/2 + U(x), U(x) = ω²(cos d − cos(d + x)) − γx
= ω²(2 cos d sin²(x/2) − sin d (x − sin x)) (the form evaluated), is non-increasing along the exact motion
(dH/dt = −βx'²).  The well of θ* is bounded by the saddles x_r = π − 2d and
x_l = −π − 2d, with U(x_r) = 2ω² cos d − γ(π − 2d), U(x_l) = 2ω² cos d + γ(π + 2d); U
increases on [0, x_r] and decreases on [x_l, 0].  If x₀ ∈ (x_l, x_r) and
H₀ < min(U(x_l), U(x_r)), the exact motion stays in the well for all later t, with
|x(t)| ≤ A = max(A₊, A₋), A± the roots of U = H₀ on either side (Newton from the
linear amplitude sqrt(2H₀/ω_l²), or bisection where Newton does not converge; either
way the point kept has U ≥ H₀, checked, so A is an upper bound).  Near the saddle or a bifurcation
(|γ| → ω²: the barrier → 0) no A exists or A is large, and the switch waits.

(L4) Bound on the neglected remainder.  e = x − x_lin solves e'' + βe' + ω_l² e =
−ω² r(x(t)), e(0) = e'(0) = 0, so e = −ω² ∫ g(t − s) r(x(s)) ds with g the oscillator's
Green's function (g'' + βg' + ω_l² g = δ), and for every t ≥ 0

    |e(t)| ≤ ω² ρ(A) G₀,  |e'(t)| ≤ ω² ρ(A) G₁,  G₀ = ∫₀^∞ |g|,  G₁ = ∫₀^∞ |g'|.

Under-damped, g = E sin(st)/s, |sin(st)/s| ≤ min(t, 1/s):
G₀ ≤ min(4/β², 2/(βs)), and g' = E (cos st − (β/2) sin(st)/s) gives
G₁ ≤ 2/β + min(2/β, 1/s).  Over-damped or critical, g ≥ 0, so G₀ = ∫g = 1/ω_l²
exactly, and g rises once and decays, so G₁ = 2 max g; g = e^{λ₁t}(1 − e^{−2μt})/(2μ)
≤ min(t, 1/(2μ)) e^{λ₁t} gives G₁ ≤ 2 min(1/(e|λ₁|), 1/(2μ)) (critical: 4/(eβ), exact).

(L5) Switch rule.  The run switches when ω² ρ(A) G₀ ≤ SWITCH_SAFETY · (atol + rtol·|θ*|)
and ω² ρ(A) G₁ ≤ SWITCH_SAFETY · atol: after the switch every output differs from the
exact motion through the state reached by at most that, for any horizon (the error
the run carried into the switch is then propagated by a contracting linear flow).
Rounding in H₀ and U is covered by the margin AMPLITUDE_MARGIN on A.

(L6) Second order (under-damped, s² > 0).  L4's G₀ grows like 1/β: it bounds the
response to the quadratic term −ω² r₂(x) = (γ/2)x² as if that forcing resonated, which
it does not (x_lin² has frequencies 0 and 2s).  The second-order form x_L = x_lin + x₂
solves it exactly: with z = C e^{λt}, λ = −β/2 + is, C = x₀ − i b/s (x_lin = Re z),
x_lin² = (Re(z²) + |z|²)/2, and x₂'' + βx₂' + ω_l² x₂ = (γ/4)(Re(C² e^{2λt}) + |C|² e^{−βt}),
x₂(0) = x₂'(0) = 0, is

    x₂ = e^{−βt}(Q_r cos 2st − Q_i sin 2st) + M e^{−βt} + E·(D_r cos st − D_i sin st),

Q = (γ/4)C²/P(2λ), M = (γ/4)|C|²/ω_l², P(μ) = μ² + βμ + ω_l² (P(2λ) = ω_l² − 4s² − 2iβs,
never 0: no resonance), D_r = −(Q_r + M), D_i = (x_p'(0) − (β/2)D_r)/s with
x_p'(0) = −βQ_r − 2sQ_i − βM (the homogeneous part that makes x₂(0) = x₂'(0) = 0).
|x₂| ≤ X₂ = |Q| + |M| + |D| for all t ≥ 0.

(L7) Its bound.  e₂ = x − x_L solves the oscillator forced by −ω²(r(x) − r₂(x_lin)), and
|r(x) − r₂(x)| ≤ ρ₃(A) = cos d·A³/6 + |sin d|·A⁴/24 (Lagrange remainders of sin and cos),
|r₂(x) − r₂(x_lin)| = (|sin d|/2)|x − x_lin||x + x_lin| ≤ (|sin d|/2)(X₂ + E)(A + |C|),
E = sup|e₂| (finite: x, x_L are bounded), so with q = ω²G₀(|sin d|/2)(A + |C|) < 1

    E ≤ ω²G₀ (ρ₃(A) + (|sin d|/2)(A + |C|)X₂) / (1 − q),
    sup|e₂'| ≤ ω²G₁ (ρ₃(A) + (|sin d|/2)(A + |C|)(X₂ + E)).

The neglected terms are cubic, not quadratic, in A: on P4 (β = 0.01, γ = 0.3) at
1e-10 the switch comes at A ≈ 6e-5 instead of 7e-7, a third of the transient earlier.
The run takes the first-order form where its bound passes (L5), else the second-order
one where this bound does (:func:`locked_choice`); the switch rule is L5's for either.

RUNNING cycle (β > 0; a rotation settling on the limit cycle θ(t + T_c) = θ(t) ± 2π):

(R1) Section.  After each window the loop looks for a crossing of a level
θ = θ_s + 2πm inside it (the window's formula, safeguarded Newton on θ(s) − θ_s − 2πm):
the crossings (t_n, v_n) of successive levels in one direction are the return map of
the section θ ≡ θ_s (mod 2π).  θ_s = π − d is the saddle, the top of the tilted
potential's barrier (d = arcsin(γ/ω²), clamped to ±π/2 when |γ| ≥ ω², where no
equilibrium exists and every level is crossed alike; :func:`section_offset`): a
motion trapped in a well never reaches it, so a librating or settling run does no
section work (at θ ≡ 0 every swing through the bottom of the well was a crossing,
solved by Newton: a quarter of P1's run time).

(R2) Convergence.  Near the cycle the return map contracts geometrically: the flow's
divergence is −β, so the cycle's non-trivial Floquet multiplier, the slope of the
return map there, is μ = e^{−βT_c} (Liouville); the loop measures it as
μ = |v_n − v_{n−1}| / |v_{n−1} − v_{n−2}|.  The deviations still to come sum to at
most |Δv|·μ/(1 − μ) in v and |ΔT|·μ/(1 − μ) in the period; the period's error repeats
in each of the N periods left to t_bound, so it shifts the phase by up to
N·|ΔT|/(1 − μ).  The run switches when μ ≤ CYCLE_MAX_MULTIPLIER,
|Δv|/(1 − μ) ≤ SWITCH_SAFETY · (atol + rtol·|v_n|), N|ΔT|/(1 − μ) · max|θ''| within the
same, and N|ΔT|/(1 − μ) · max|θ'| ≤ SWITCH_SAFETY · (atol + rtol·|θ_n|)
(:func:`cycle_switch`): the longer the horizon, the later (by log N periods) the switch.
From there the period is averaged over CYCLE_AVERAGE_PERIODS more returns, and the
last crossing is the cycle's anchor.

(R3) Extension.  After the switch the motion is the last period's, shifted: with
τ = t − t_n = nT_c + s (0 ≤ s < T_c), θ(t) = θ_p(s) ± 2πn, where θ_p is the run
re-taken from the anchor (θ_s + 2πm, v_n) by the same approximant and controller (the
windows of one period, a function of the anchor only, so every path and the dense
output give the same value; they are re-taken once per call of the loop or of the
dense output and each output is looked up in them, whatever the horizon).  Its error per period is the ordinary windows' (one period
of them), and its phase error grows with n·ΔT as the ordinary run's would: the
extension is the ordinary run without the windows between outputs, not a bound
tighter than it (the phase of a limit cycle is neutral).

LIBRATION (β = 0, |γ| < ω²; a conservative motion trapped in a well of the tilted
potential, exactly periodic from its first instant):

(C1) Energy and trapping.  With β = 0, H = θ'²/2 + V(θ), V = −ω² cos θ − γθ, is
constant.  The angle is reduced by 2π into the well of d = arcsin(γ/ω²) (a double:
any reference near the bottom serves), φ ∈ (−π − d, π − d], and with x = φ − d

    U(x) = V(d + x) − V(d) = 2ω² cos d sin²(x/2) + (ω² sin d − γ) sin x − γ(x − sin x),

an identity whose terms carry no cancellation (ω² sin d − γ is the rounding of d,
~1e-16, formed in double-double; x − sin x by its series below X_MINUS_SIN_SERIES).
The motion is trapped when x lies between the saddles x_l = −π − 2d, x_r = π − 2d and
H' = θ'²/2 + U(x) is below both U(x_l) and U(x_r) (as L3): it librates between the
turning points x₋ < 0 < x₊, U(x±) = H' (Newton in double, then
LIBRATION_DD_NEWTON steps in double-double), with period T.

(C2) Period.  T = 2∫ dx / sqrt(2(H' − U)) over [x₋, x₊]; with x = m + r sin ψ (m, r
the midpoint and half-width of [x₋, x₊]), T = 2∫_{−π/2}^{π/2} g dψ,
g(ψ) = r cos ψ / sqrt(2F(x(ψ))), F = H' − U.  g is analytic (F vanishes like cos²ψ at
ψ = ±π/2) and extends to a 2π-periodic function (g(π − ψ) = g(ψ)), so the midpoint
rule T_M = (2π/M) Σ g(ψ_j), ψ_j = −π/2 + (j + ½)π/M, is the trapezoidal rule on a
periodic analytic function and converges geometrically.  Every step is in
double-double; M doubles from LIBRATION_NODES_MIN until
|T_M − T_{M/2}| ≤ LIBRATION_QUAD_RTOL · T_M.  Once the convergence is geometric the
error of T_M is far below that of T_{M/2}, which |T_M − T_{M/2}| measures, so
δT = |T_M − T_{M/2}| + LIBRATION_DD_FLOOR · T_M bounds |T_M − T| (tested against
mpmath at 50 digits).  Near the separatrix T diverges logarithmically, g has a
near-singularity, and without convergence by LIBRATION_NODES_MAX there is no switch.

(C3) Extension.  θ(t₀ + nT + s) = θ_p(s), θ_p the run re-taken from the anchor (the
initial state) by the same approximant and controller over one period: the running
cycle's R3 with winding sign 0.  An output's error is θ_p's own (the ordinary windows'
over at most one period, not growing with the horizon) plus the phase error of the
stored period, |θ_p(s') − θ_p(s)| ≤ v_max·n·δT with v_max = sqrt(2H') (the speed at
x = 0, where U = 0).  T is stored in double-double and s = τ − nT formed with an
exact product, so T's rounding to a double (1e-16·T a period) does not accumulate.

(C4) Switch rule.  At the run's first window, when N·δT·v_max ≤ SWITCH_SAFETY ·
(atol + rtol·θ_min) and N·δT·(ω² + |γ|) ≤ SWITCH_SAFETY · atol (|θ''| ≤ ω² + |γ|),
N the periods to t_bound plus one and θ_min ≤ |θ| over the orbit, and the span holds
at least LIBRATION_MIN_PERIODS periods (shorter runs are cheaper window by window).

PHASE-LOCKED to the drive (β > 0, A ≠ 0, Ω > 0; a driven run settling on a periodic
orbit of the stroboscopic map, θ(t + T_d) = θ(t) + 2πp, T_d = 2π/Ω: a Shapiro step;
S7 for θ(t + qT_d) = θ(t) + 2πp, the fractional steps):

(S1) Samples.  The stroboscopic map P takes the state at t to the state at t + T_d.
The loop samples z_n = (θ, θ') at t_n = t_s + nT_d (t_s the run's start, n ≥ 1) by the
formula of the window holding t_n, as outputs are.  t_s + nT_d is formed in
double-double (:func:`strobe_period`, :func:`strobe_time`): t_n is its rounding and
r_n = (t_s + nT_d) − t_n its residual, |r_n| ≤ ulp(t_n)/2, and the sample is carried to
the exact stroboscopic time to first order, (θ + θ'r_n, θ' + θ''r_n) with θ'' from the
equation, so the deviations below have no floor θ''·ulp(t_n) growing with t.  The
deviation Δ_n = (θ_{n+1} − θ_n − 2πp, θ'_{n+1} − θ'_n), p the nearest integer to
(θ_{n+1} − θ_n)/2π, is formed on the winding count and φ (mbm.loop "Winding"), free of
the rounding of |θ|.

(S2) Liouville.  The flow's divergence is −β everywhere, so det DP(z) = e^{−βT_d} =: D
at every z, exactly (not an estimate).  Near a fixed point z* of P (mod 2πp),
Δ_{n+1} = MΔ_n + O(|Δ_n|²), M = DP(z*), and its multipliers have μ₁μ₂ = D: a complex
pair has |μ| = √D, a real pair μ₂ = D/μ₁.

(S3) Tail.  By Cayley–Hamilton M² = τM − D·I (τ = tr M = μ₁ + μ₂), so
M^k = U_{k−1}M − D·U_{k−2}, U_j = Σ_{i=0}^{j} μ₁^i μ₂^{j−i}, |U_j| ≤ (j + 1)ρ^j,
ρ = max |μ_i|.  With x₀ = Δ_{N−2}, x₁ = Δ_{N−1} the last two deviations, the later ones
x_k = U_{k−1}x₁ − D·U_{k−2}x₀ obey |x_k| ≤ kρ^{k−1}|x₁| + (k − 1)Dρ^{k−2}|x₀| in any
norm, so for ρ < 1

    Σ_{k≥2} |x_k| ≤ B = |x₁|((1 − ρ)^{−2} − 1) + D|x₀|(1 − ρ)^{−2},

whatever the multipliers: complex, real or equal (the (1 − ρ)^{−2} covers the
defective case).  A ratio of successive |Δ| is no such bound: with complex
multipliers the ratios oscillate about √D, above it half the time, and in a skewed
eigenbasis above 1.

(S4) Measured multipliers.  Each triple of successive deviations satisfies
x₂ + D·x₀ = τx₁ in both components, so the last four deviations (θ components
weighted by ω) give four equations for the one unknown τ, solved by least squares
(:func:`strobe_switch`).  From τ and the exact D: τ² < 4D is a complex pair, ρ = √D;
else ρ = (|τ| + √(τ² − 4D))/2.  Because D is exact, one decaying mode is enough: a run
passing a saddle orbit (μ₁ > 1 > μ₂ = D/μ₁), its deviations shrinking like μ₂ⁿ while
the unstable part is still small, fits τ = μ₂ + D/μ₂ and shows ρ = μ₁ > 1.  The fit is
trusted only when (a) its residual is at most STROBE_FIT_RESIDUAL of |x₁| (the linear
model holds: a transient far from the orbit, chaos or a run between steps fails it);
(b) the fits of three successive samples agree to STROBE_TRACE_AGREE (at the noise
floor a fit of noise passes (a) now and then, with any τ: measured, one in ~30; three
that agree rarely do); ρ is then taken at the largest |τ| of the three, widened by
their spread and by STROBE_NOISE_WIDEN residuals times 1 + |τ| (the noise's share of
τ: the residual is relative to |x₁|), and ρ does not decrease as |τ| grows, so a fit
biased by the noise is covered; (c) ρ is not below that of the last clean fit
(residual ≤ STROBE_CLEAN_RESIDUAL: deviations far above the noise), and there has
been one: at the computed map's noise floor (its controller's window choices, 1e-4 to
1e-3 of the tolerance) the noise itself can fit three agreeing traces, of any value
(measured: a complex pair on a run whose multipliers are real, 0.83 and 0.34).  Near
τ² = 4D (equal multipliers) ρ is most sensitive to τ, and a run there may not switch
at tight tolerances, where the deviations reach the switch level only near the noise
floor.

(S5) Switch rule.  In the norm |x| = √(ω²x_θ² + x_v²) the run switches at sample N when
the last four deviations share one p, the fits pass (S4), ρ ≤ STROBE_MAX_MULTIPLIER and
B ≤ SWITCH_SAFETY · min(atol + rtol·|θ'_N|, ω(atol + rtol·|θ_N|)) (S3, ρ from S4).  As
z_{N+n} − z_N = Σ_{k=N}^{N+n−1} Δ_k, every later stroboscopic sample differs from the
anchor z_N by at most B: within SWITCH_SAFETY of the tolerance scale in θ' and in ωθ
(θ is weighted by ω, not left at rtol·|θ| of the wound angle: on an orbit locked to
the drive a θ offset is not neutral, it becomes a θ' error within a period).  Between
samples the deviation is carried by the flow over less than one drive period, as an
error of the ordinary run at a sample is (the extension is the ordinary run from the
anchor, S6).  Near a step's edge (a saddle-node of P: μ₁ → 1) ρ passes
STROBE_MAX_MULTIPLIER and the run waits; between steps (quasi-periodic motion) and on
chaotic motion the deviations do not decay and the fit fails: no switch.  A
subharmonic orbit (θ(t + qT_d) = θ(t) + 2πp, q > 1) is no fixed point of P: its
period-1 deviations do not decay, and S7 takes it.

(S6) Extension.  After the switch the motion is one stored drive period re-taken from
the anchor (t_a = t_N, the anchor state the window's formula there): with
t − t_a = nT_d + s, 0 ≤ s < T_d (:func:`strobe_split`: t − t_a exact, nT_d in
double-double, so s has no n·eps·T_d drift), θ(t) = θ_p(s) + 2πpn, θ_p the run from the
anchor at local time 0 with the drive's phase Ωs + ψ_a, ψ_a = Ωt_a + φ reduced to
[−π, π] in double-double (:func:`strobe_phase`): the re-run's drive is the drive at
t_a + s to a few ulps of π, for any n.  The re-run is the same approximant and
controller (tolerance scale from the anchor's winding count), a function of the
anchor only, so every path and the dense output give the same bits, and an evaluation
costs at most one period of windows (a run whose last period took more than half
CYCLE_MAX_WINDOWS, the re-run's limit, does not switch).  Unlike the running cycle's (R3) the period is
exact and the orbit has no neutral direction, so the extension's error does not grow
with n: it is the anchor's deviation (S5) plus one period of the ordinary windows'
error.  The result's period is T_d and its mean velocity pΩ (:func:`strobe_summary`;
q drive periods and pΩ/q for the orbits of S7).

(S7) Subharmonic orbits (q > 1).  An orbit θ(t + qT_d) = θ(t) + 2πp, q > 1 (a
fractional step, ⟨θ'⟩ = (p/q)Ω, or a period-doubled one) is a fixed point of P^q.
After S5's test at each sample z_N (q = 1 first), the maps P^q, q = 2 ..
STROBE_MAX_PERIODS (smallest first), are tested on the same samples: the deviations
Δ^q_i = z_i − z_{i−q} − 2πp (S1's arithmetic, p the turns over q periods), the four
of the anchor's class Δ^q_{N−3q}, Δ^q_{N−2q}, Δ^q_{N−q}, Δ^q_N sharing one p, and
S2–S5 word for word with P^q for P: det DP^q = e^{−βqT_d} exactly (Liouville over
qT_d), the tail B of S3 over the samples N + jq, the fit and its trust (S4: the three
successive fits are at the samples N − 2, N − 1, N, of different classes, and estimate
one trace: DP^q at z_{i+1} is DP(z_i)·DP^q(z_i)·DP(z_i)^{−1}), ρ ≤
STROBE_MAX_MULTIPLIER and B within S5's scale.  Each class c (the samples i ≡ c mod q)
keeps its last finite tail bound B_c (void once its four deviations' turns disagree):
by S3, B_c bounds the sum of all the class's deviations after the sample it was fitted
at, so every later sample of the class is within B_c of the class's limit z*_c, a point
of the exact orbit.  The switch asks B_c within the scale for every class, not the
anchor's alone: then every later sample, the extension's among them (S6: the re-run
from z_N is the ordinary run's continuation), is within the scale of the orbit's, and
between samples the deviation is carried by the flow over less than one drive period,
as in S5.  The anchor's class alone would not do: the flow over i < q drive periods
can amplify its deviation (measured: by 50 over two drive periods on β = 0.5, γ = 0.52,
A = 2, Ω = 0.5, q = 4, where the extension was then 2.7 tolerances off).

The smallest q.  A fixed point of P^d is one of P^q for every multiple q of d, and
there P^q contracts faster (its multipliers are those of P^d to the power q/d): on an
orbit of period d, P^q's bound can pass before P^d's.  So the switch to q also asks
that the orbit's period is no proper divisor d of q: with
sep_d = |z_N − z_{N−d} − 2πm| (S5's norm, m the nearest integer) the limits of the
classes of N and N − d differ by at least sep_d − B_N − B_{N−d}, and the rule asks
that this exceed STROBE_DISTINCT·scale for every d | q, d < q.  On an orbit of period d
those two limits coincide (mod 2π: the class of N − d is the image of N's under
P^{q−d}, and q − d is a multiple of d), so no orbit of period d is reported as q: a
q = 1 orbit never as q = 2 (a run that switched under S5 switches at the same sample,
bit for bit), a q = 2 orbit never as q = 4.  Orbits of more than STROBE_MAX_PERIODS
drive periods are not detected: the ordinary run continues.

The extension is S6 with qT_d for T_d: one stored period of q drive periods re-taken
from the anchor (split on qT_d in double-double; the drive's phase Ωs + ψ_a, s < qT_d),
θ(t) = θ_p(s) + 2πpn; an evaluation costs at most q drive periods of windows (a run
whose last q periods took more than half CYCLE_MAX_WINDOWS does not switch).  The
result's period is qT_d and its mean velocity pΩ/q (:func:`strobe_summary`; p and q
may share a factor: a period-doubled orbit of the n = 1 step is p = q = 2, ⟨θ'⟩ = Ω).
The computed map's noise per sample is that of q drive periods of windows (measured
1e-3 to 1e-2 of the tolerance at q = 4): with ρ near STROBE_MAX_MULTIPLIER the
deviations can reach it before B passes, and such a run may not switch at some
tolerances (as S4's near τ² = 4D).
"""

import math

import numba
import numpy as np

from .special.dd import (
    PI_HI,
    PI_LO,
    PIO2_HI,
    PIO2_LO,
    TWO_PI_HI,
    TWO_PI_LO,
    dd_add,
    dd_div,
    dd_div_d,
    dd_mul,
    dd_mul_d,
    dd_sincos,
    dd_sincos_any,
    dd_sqrt,
    reduce_2pi,
    two_prod,
    two_sum,
)

__all__ = [
    "SWITCH_SAFETY",
    "REGIME_NONE",
    "REGIME_LOCKED",
    "REGIME_NAMES",
    "LOCKED_TAG",
    "LOCKED_WIDTH",
    "locked_constants",
    "section_offset",
    "locked_quick_reject",
    "locked_amplitude",
    "locked2_terms",
    "locked2_bound",
    "locked2_quick",
    "locked_choice",
    "LOCKED2_WIDTH",
    "locked_bound",
    "locked_coef",
    "locked_eval",
    "locked_eval_array",
    "green_integrals",
    "REGIME_RUNNING",
    "CYCLE_TAG",
    "CYCLE_WIDTH",
    "cycle_coef",
    "cycle_switch",
    "cycle_summary",
    "REGIME_LIBRATION",
    "libration_period",
    "REGIME_PHASE_LOCKED",
    "STROBE_TAG",
    "STROBE_WIDTH",
    "strobe_period",
    "strobe_time",
    "strobe_phase",
    "strobe_split",
    "strobe_switch",
    "strobe_coef",
    "strobe_summary",
    "STROBE_MAX_PERIODS",
    "STROBE_RING",
]

# (L5): the remainder bound must be this fraction of the tolerance, so the switch adds
# at most a tenth of one window's allowed error to the outputs after it.
SWITCH_SAFETY = 0.1
# (L3): relative widening of the amplitude bound A, covering the rounding of H₀ and U
# (a few ulps of each) with orders of magnitude to spare.
AMPLITUDE_MARGIN = 1e-8
# (L3): bisection steps for A± (each halves a bracket of length ≤ 2π: 60 reach ulps).
AMPLITUDE_BISECTIONS = 60
# (L3): Newton steps for A± from the linear amplitude (quadratic convergence: 3-5
# reach ulps near the bottom of the well; bisection takes over if they do not certify).
AMPLITUDE_NEWTON_STEPS = 8
# Below this |x|, x − sin x by its series to x¹¹ (the next term is below 1e-15 of it).
X_MINUS_SIN_SERIES = 0.25
# Quick rejection before the rigorous test (it only delays a switch, never allows
# one): the linear estimate sqrt(2H/ω_l²) of A times this factor must already pass.
QUICK_FACTOR = 0.5

REGIME_NONE = 0
REGIME_LOCKED = 1
REGIME_RUNNING = 2
REGIME_LIBRATION = 3
REGIME_PHASE_LOCKED = 4
#: The name of each regime (``regime`` of a result).
REGIME_NAMES = {REGIME_NONE: None, REGIME_LOCKED: "locked", REGIME_RUNNING: "running",
                REGIME_LIBRATION: "libration", REGIME_PHASE_LOCKED: "phase-locked"}

# A locked window's coefficient vector, as stored in a run's window store:
# [LOCKED_TAG, θ₀, x₀ = θ₀ − θ*, v₀, β/2, s², ω_l²], θ = θ₀ + (x − x₀) so that the
# window's start is its anchor bit for bit.  coef[0] of an approximant's window is its
# anchor status, 0.0, so the tag tells a locked window from any other.
LOCKED_TAG = 101.0
LOCKED_WIDTH = 7
# The second-order window (L6) appends [2.0, Q_r, Q_i, M, D_r, D_i]: coef[7] = 2 marks it
# (a first-order vector stored zero-padded reads 0 there).
LOCKED2_WIDTH = 13
# A running-cycle window's coefficient vector (R3): [CYCLE_TAG, θ_c, v_c, T_c, t_off,
# β, γ, ω, rtol, atol, winding sign, kind argument, error order, k_c, T_lo]; t_off is
# the time from the cycle's anchor crossing to the window's start, the anchor is at
# θ = 2πk_c + θ_c (the loop's winding count, mbm.loop "Winding"), and T_c + T_lo is
# the period in double-double (T_lo = 0 for the running cycle; C3 for a libration).
CYCLE_TAG = 102.0
CYCLE_WIDTH = 15
# (R2): a return map whose contraction measured over two periods is above this is not
# (yet) converging geometrically: no switch.
CYCLE_MAX_MULTIPLIER = 0.9
# (R2): once the map has converged, the period is averaged over this many more
# returns: the crossing times carry the run's global error, which a single
# difference would repeat in every later period; averaged, the stored period's
# drift is the run's own mean drift per period.
CYCLE_AVERAGE_PERIODS = 32
# (R1): safeguarded Newton steps for a section crossing inside a window (quadratic
# convergence from the bracket's secant start: a handful suffice; bisection backs it up).
CROSSING_ITERATIONS = 60
# (C2): first and last node counts of the period's quadrature (doubling): 16 nodes
# reach 1e-25 on small librations; past 2**13 the orbit is at the separatrix, no switch.
LIBRATION_NODES_MIN = 16
LIBRATION_NODES_MAX = 8192
# (C2): the quadrature stops when two successive T_M agree to this (double-double
# carries ~1e-30; this leaves the stored period 1e9 times more exact than a double).
LIBRATION_QUAD_RTOL = 1e-25
# (C2): added to δT, relative: the double-double rounding of the sum and of g (a
# few ulps of 2**-104 times the cancellation of F near the turning points).
LIBRATION_DD_FLOOR = 1e-27
# (C1): double-double Newton steps on the turning points from the double root
# (quadratic: one reaches ~1e-32, the second confirms).
LIBRATION_DD_NEWTON = 3
# (C1): a bracketed Newton in double for the turning points (bisection backs it up).
LIBRATION_NEWTON_STEPS = 100
# (C1): no switch below this amplitude (rad): F's relative precision near the turning
# points scales like 1e-32/r², and at rest there is nothing to extend.
LIBRATION_MIN_AMPLITUDE = 1e-6
# (C1): the energy must be this far (times ω²) below the barrier for the double test
# of trapping to be sure of its answer (the quadrature then judges the separatrix).
LIBRATION_BARRIER_MARGIN = 1e-9
# (C4): spans shorter than this many periods are run window by window (the extension
# re-takes up to a period of windows per output: it pays only over many periods).
LIBRATION_MIN_PERIODS = 16
# (C1): below this |x| the double-double x − sin x by its series (23 terms past x³
# reach 1e-33 relative at 0.25).
DD_X_MINUS_SIN_TERMS = 12
# (R3): most windows one evaluation of the stored period may take (a period takes
# ~10-100 at the tolerances in use); past it the evaluation is NaN (a failure).
CYCLE_MAX_WINDOWS = 100000

# Phase-locked to the drive (S1-S7).
# A phase-locked window's coefficient vector (S6): [STROBE_TAG, φ_a, θ'_a, k_a, t_a, q, p,
# ψ_a, β, γ, ω, A, Ω, rtol, atol, karg + STROBE_CODE·error_order]: the anchor at
# θ = 2πk_a + φ_a, θ'_a at time t_a, the period qT_d (q ≥ 1, S7), p turns per period, ψ_a
# the drive's phase at t_a reduced to [−π, π].  16 wide: the narrowest Taylor vector
# (taylor8: 5 + 11) holds it, so every path can store it.
STROBE_TAG = 103.0
STROBE_WIDTH = 16
# (S6): karg and error_order share one entry (both below it; exact in a double).
STROBE_CODE = 1024
# (S5): a stroboscopic map whose spectral radius (from the fitted trace and the exact
# determinant) is above this converges too slowly to trust the fits: no switch.  The
# switch comes at |Δ| ≈ SWITCH_SAFETY·tol·(1 − ρ)², and the computed map's own noise
# (the controller's window choices) is 1e-4 to 1e-3 of tol (measured on the n = 1 step
# of β = 0.2, A = 2, Ω = 1 at 1e-4 to 1e-8): at ρ = 0.8 the deviations are still
# 4 to 40 times the noise, at 0.9 they were as small as it (a run with ρ = 0.994 then
# fitted 0.89 and switched at 1e-6).
STROBE_MAX_MULTIPLIER = 0.8
# (S4): the least-squares residual of x₂ + D·x₀ = τx₁ over the four equations, relative
# to |x₁|, above which the deviations are not (yet) the linear map's: no switch.
# Measured on the n = 1 step of β = 0.2, A = 2, Ω = 1: 1e-7 to 1e-3 while the
# deviations are 1e3 times the computed map's noise or more, 1e-2 to 1 at its floor.
STROBE_FIT_RESIDUAL = 0.05
# (S4): the noise's share of τ taken as this many residuals (relative to |x₁|) times
# 1 + |τ|, the coefficients of x₀-free noise in x₂ − τx₁: the residual of 4 equations
# with 1 unknown sees 3 of the noise's 4 degrees of freedom, so it can read low.
STROBE_NOISE_WIDEN = 2.0
# (S4): a fit with a residual below this (relative to |x₁|) is clean: the deviations are
# far above the computed map's noise, and its ρ stands until the next clean fit.  At
# the noise floor the noise itself can fit three agreeing traces (measured: τ = −0.92,
# a complex pair, on a run whose multipliers are 0.83 and 0.34), so ρ is never taken
# below the last clean fit's.  Clean fits read 1e-7 to 1e-4 on the step above.
STROBE_CLEAN_RESIDUAL = 1e-3
# (S4): the traces of three successive fits must agree to this (absolute; clean fits
# agree to 1e-4 on that step, fits of round-off noise scatter by 0.1 to 1).
STROBE_TRACE_AGREE = 0.01
# (S7): the longest orbit looked for, in drive periods (q ≤ this): each output after a
# switch re-takes up to q periods of windows and the test needs 4q + 1 samples, and
# 4 covers the widest fractional steps (p/2, p/3, p/4) and two period doublings.
STROBE_MAX_PERIODS = 4
# (S7): the samples kept for the maps P^q (the four q-deviations span 4q + 1 samples).
STROBE_RING = 4 * STROBE_MAX_PERIODS
# (S7): for each proper divisor d of q the samples d drive periods apart must differ by
# more than this many switch scales: both are within one scale of their classes'
# limits, so those differ by 98 scales, ten tolerances: the orbit's period is not d.
STROBE_DISTINCT = 100.0


@numba.njit(cache=True)
def green_integrals(beta, wl2):
    """Upper bounds on the L¹ norms of the oscillator's Green's function (item L4).

    Parameters
    ----------
    beta : float
        Damping, > 0.
    wl2 : float
        ω_l², > 0.

    Returns
    -------
    g0, g1 : float
        G₀ ≥ ∫₀^∞ |g| and G₁ ≥ ∫₀^∞ |g'| for g'' + βg' + ω_l² g = δ.
    """
    s2 = wl2 - 0.25 * beta * beta
    if s2 > 0.0:
        s = math.sqrt(s2)
        # Divided one at a time: β² may underflow (β = 1e-270), 4/β/β is then inf.
        g0 = min(4.0 / beta / beta, 2.0 / beta / s)
        g1 = 2.0 / beta + min(2.0 / beta, 1.0 / s)
    else:
        mu = math.sqrt(-s2)
        lam1 = wl2 / (0.5 * beta + mu)  # |λ₁|
        g0 = 1.0 / wl2
        g1 = 2.0 / (math.e * lam1) if mu == 0.0 else 2.0 * min(1.0 / (math.e * lam1), 0.5 / mu)
    return g0, g1


@numba.njit(cache=True)
def section_offset(gamma, omega):
    """θ_s of the running cycle's section θ ≡ θ_s (mod 2π) (item R1): the saddle π − d.

    Parameters
    ----------
    gamma, omega : float
        The model's torque and ω > 0.

    Returns
    -------
    float
        π − arcsin(γ/ω²), with γ/ω² clamped to [−1, 1].
    """
    return math.pi - math.asin(min(1.0, max(-1.0, gamma / (omega * omega))))


@numba.njit(cache=True)
def locked_constants(beta, gamma, omega):
    """Per-run constants of the locked test (items L1, L4).

    Parameters
    ----------
    beta, gamma, omega : float
        The model, β > 0 and |γ| < ω².

    Returns
    -------
    d, wl2, g0, g1 : float
        d = arcsin(γ/ω²), ω_l² = ω² cos d and :func:`green_integrals`.
    """
    w2 = omega * omega
    d = math.asin(gamma / w2)
    wl2 = w2 * math.cos(d)
    g0, g1 = green_integrals(beta, wl2)
    return d, wl2, g0, g1


@numba.njit(cache=True, inline="always")
def _rho(sd, a):
    # (L1): bound on |r(x)| for |x| ≤ a.
    return 0.5 * sd * a * a + a * a * a / 6.0


@numba.njit(cache=True, inline="always")
def _x_minus_sin(x):
    # x − sin x without cancellation: its Taylor series below X_MINUS_SIN_SERIES.
    if abs(x) < X_MINUS_SIN_SERIES:
        x2 = x * x
        return x * x2 * (1.0 / 6.0 - x2 * (1.0 / 120.0 - x2 * (1.0 / 5040.0 - x2 * (
            1.0 / 362880.0 - x2 / 39916800.0))))
    return x - math.sin(x)


@numba.njit(cache=True, inline="always")
def _potential(w2, gamma, d, x):
    # (L3): U(x) = ω²(2 cos d sin²(x/2) − sin d (x − sin x)), sin d = γ/ω²: both terms
    # carry their leading order, so U keeps its relative precision at any small x.
    h = math.sin(0.5 * x)
    return w2 * (2.0 * math.cos(d) * h * h) - gamma * _x_minus_sin(x)


@numba.njit(cache=True, inline="always")
def _nearest_k(theta, d):
    return math.floor((theta - d) / (2.0 * math.pi) + 0.5)


@numba.njit(cache=True, inline="always")
def locked_quick_reject(theta, v, d, sd, wl2, g0, omega, rtol, atol, q2):
    """True when the locked test surely fails (cheap; run before every window).

    A necessary condition only (the linear amplitude estimate times QUICK_FACTOR must
    already pass L5): a True delays a switch, a False leads to :func:`locked_bound`.

    Parameters
    ----------
    theta, v : float
        The state.
    d, wl2, g0 : float
        From :func:`locked_constants`.
    sd : float
        |sin d| (formed once per run: a sin per window was ~10 % of the test).
    omega, rtol, atol : float
        The model's ω and the run's tolerances.
    q2 : float
        ω²G₀ cos d / 6, the leading term of L7's bound per A³ (a lower estimate of
        it), or 0 where the second-order form is not available.

    Returns
    -------
    bool
    """
    k = _nearest_k(theta, d)
    ts = d + 2.0 * math.pi * k
    x = theta - ts
    a = QUICK_FACTOR * math.sqrt(x * x + v * v / wl2)
    tol = SWITCH_SAFETY * (atol + rtol * abs(ts))
    if omega * omega * _rho(sd, a) * g0 <= tol:
        return False
    return not (q2 > 0.0 and q2 * a * a * a <= tol)


@numba.njit(cache=True, inline="always")
def _amplitude_newton(w2, gamma, d, wl2, h0, edge):
    # (L3): a point x between 0 and the saddle ``edge`` with U(x) ≥ H₀, so that the
    # root A± of U = H₀ on that side (U is monotone there) is at most |x|; inf if
    # none was certified.  Newton on U(x) = H₀ (U' = ω² sin(d + x) − γ) from the
    # linear amplitude sqrt(2H₀/ω_l²): a few steps instead of AMPLITUDE_BISECTIONS
    # (the test runs before windows near the equilibrium: 2.7 µs bisected, 0.2 here).
    if h0 <= 0.0:
        return 0.0
    x = math.copysign(math.sqrt(2.0 * h0 / wl2), edge)
    for _ in range(AMPLITUDE_NEWTON_STEPS):
        du = w2 * math.sin(d + x) - gamma
        if not (du * edge > 0.0):
            return math.inf
        x_new = x - (_potential(w2, gamma, d, x) - h0) / du
        if not (0.0 < x_new / edge < 1.0):
            return math.inf
        if x_new == x:
            break
        x = x_new
    # Certify: U(x) ≥ H₀ at x or at x pushed outwards by a growing fraction.
    widen = AMPLITUDE_MARGIN
    for _ in range(4):
        if abs(x) < abs(edge) and _potential(w2, gamma, d, x) >= h0:
            return x
        x *= 1.0 + widen
        widen *= 1e3
    return math.inf


@numba.njit(cache=True)
def locked_bound(beta, gamma, omega, theta, v, d, wl2, g0, g1):
    """Rigorous bounds on the locked closed form's deviation over any horizon (L3, L4).

    Parameters
    ----------
    beta, gamma, omega : float
        The model, β > 0 and |γ| < ω².
    theta, v : float
        The state the closed form is anchored at.
    d, wl2, g0, g1 : float
        From :func:`locked_constants`.

    Returns
    -------
    theta_star : float
        The nearest stable equilibrium d + 2πk.
    bound_theta, bound_v : float
        sup over t ≥ 0 of |θ − θ_lin| and |θ' − θ_lin'| between the exact motion and
        :func:`locked_eval` from this state; inf when the state is not trapped in the
        well of θ* (on or above its lower saddle).
    """
    ts, amp = locked_amplitude(gamma, omega, theta, v, d)
    r = omega * omega * _rho(abs(math.sin(d)), amp)
    return ts, r * g0, r * g1


@numba.njit(cache=True)
def locked_amplitude(gamma, omega, theta, v, d):
    """The nearest stable equilibrium and the amplitude bound A of item L3.

    Returns
    -------
    theta_star : float
        d + 2πk nearest θ.
    amp : float
        A ≥ sup_t |θ(t) − θ*| of the exact motion from (θ, θ'); inf when the state is
        not trapped in the well of θ*.
    """
    w2 = omega * omega
    k = _nearest_k(theta, d)
    ts = d + 2.0 * math.pi * k
    x = theta - ts
    xr = math.pi - 2.0 * d
    xl = -math.pi - 2.0 * d
    ur = 2.0 * w2 * math.cos(d) - gamma * (math.pi - 2.0 * d)
    ul = 2.0 * w2 * math.cos(d) + gamma * (math.pi + 2.0 * d)
    h0 = 0.5 * v * v + _potential(w2, gamma, d, x)
    barrier = min(ur, ul)
    if not (xl < x < xr) or not (h0 * (1.0 + AMPLITUDE_MARGIN) < barrier):
        return ts, math.inf
    amp = 0.0
    wl2 = w2 * math.cos(d)
    for side in range(2):
        edge = xr if side == 0 else xl
        hi = _amplitude_newton(w2, gamma, d, wl2, h0, edge)
        if not hi < math.inf:
            # Newton did not certify a root (far from the bottom of the well): bisection.
            lo = 0.0
            hi = edge
            for _ in range(AMPLITUDE_BISECTIONS):
                mid = 0.5 * (lo + hi)
                if _potential(w2, gamma, d, mid) >= h0:
                    hi = mid
                else:
                    lo = mid
        amp = max(amp, abs(hi))
    return ts, max(amp, abs(x)) * (1.0 + AMPLITUDE_MARGIN)


@numba.njit(cache=True)
def locked2_terms(beta, gamma, wl2, x0, v0):
    """The second-order term x₂ of item L6 from the anchor offset (x₀, x₀').

    Returns
    -------
    qr, qi, m, dr, di : float
        Q, M, D of L6 (under-damped: s² = ω_l² − β²/4 > 0).
    c_abs : float
        |C| = sqrt(x₀² + (b/s)²), b = x₀' + βx₀/2 (sup |x_lin| over t ≥ 0).
    x2 : float
        X₂ = |Q| + |M| + |D| ≥ sup |x₂|.
    """
    hb = 0.5 * beta
    s = math.sqrt(wl2 - hb * hb)
    b = v0 + hb * x0
    cr, ci = x0, -b / s
    kq = 0.25 * gamma
    # C² / P(2λ), P(2λ) = (ω_l² − 4s²) − 2iβs.
    c2r, c2i = cr * cr - ci * ci, 2.0 * cr * ci
    pr, pi = wl2 - 4.0 * s * s, -2.0 * beta * s
    den = pr * pr + pi * pi
    qr = kq * (c2r * pr + c2i * pi) / den
    qi = kq * (c2i * pr - c2r * pi) / den
    c_abs2 = cr * cr + ci * ci
    m = kq * c_abs2 / wl2
    dr = -(qr + m)
    xp1 = -beta * qr - 2.0 * s * qi - beta * m
    di = (xp1 - hb * dr) / s
    x2 = math.hypot(qr, qi) + abs(m) + math.hypot(dr, di)
    return qr, qi, m, dr, di, math.sqrt(c_abs2), x2


@numba.njit(cache=True)
def locked2_bound(beta, gamma, omega, d, wl2, g0, g1, amp, x0, v0):
    """L7's bounds on the second-order form's deviation over any horizon.

    Parameters
    ----------
    beta, gamma, omega : float
        The model (under-damped about θ*: ω_l² > β²/4).
    d, wl2, g0, g1 : float
        From :func:`locked_constants`.
    amp : float
        A from :func:`locked_amplitude`.
    x0, v0 : float
        The anchor's offset θ − θ* and θ'.

    Returns
    -------
    bound_theta, bound_v : float
        sup over t ≥ 0 of |θ − θ_L| and |θ' − θ_L'|; inf where q ≥ 1 or A is inf.
    """
    if not (amp < math.inf) or not (wl2 - 0.25 * beta * beta > 0.0):
        return math.inf, math.inf
    w2 = omega * omega
    sd = abs(math.sin(d))
    _, _, _, _, _, c_abs, x2 = locked2_terms(beta, gamma, wl2, x0, v0)
    rho3 = math.cos(d) * amp * amp * amp / 6.0 + sd * amp * amp * amp * amp / 24.0
    lip = 0.5 * sd * (amp + c_abs)
    q = w2 * g0 * lip
    if not (q < 1.0):
        return math.inf, math.inf
    e = w2 * g0 * (rho3 + lip * x2) / (1.0 - q)
    ev = w2 * g1 * (rho3 + lip * (x2 + e))
    return e, ev


@numba.njit(cache=True)
def locked_choice(beta, gamma, omega, theta, v, d, wl2, g0, g1, rtol, atol, off, second):
    """Whether the locked closed form may take over from (θ, θ'), and of which order (L5, L7).

    Parameters
    ----------
    beta, gamma, omega : float
        The model, β > 0, |γ| < ω².
    theta, v : float
        The state (θ reduced by the loop's winding: ``off`` + θ is the angle).
    d, wl2, g0, g1 : float
        From :func:`locked_constants`.
    rtol, atol : float
        The run's tolerances.
    off : float
        2π × the winding count (the tolerance's scale is that of the whole angle).
    second : bool
        Whether the second-order form may be taken (room for LOCKED2_WIDTH).

    Returns
    -------
    order : int
        0 (no switch), 1 (L2) or 2 (L6): the first-order form where its bound passes.
    theta_star : float
        The equilibrium (of θ's reduced value).
    """
    ts, amp = locked_amplitude(gamma, omega, theta, v, d)
    if not (amp < math.inf):
        return 0, ts
    tol_t = SWITCH_SAFETY * (atol + rtol * abs(off + ts))
    tol_v = SWITCH_SAFETY * atol
    r = omega * omega * _rho(abs(math.sin(d)), amp)
    if r * g0 <= tol_t and r * g1 <= tol_v:
        return 1, ts
    if second:
        bt, bv = locked2_bound(beta, gamma, omega, d, wl2, g0, g1, amp, theta - ts, v)
        if bt <= tol_t and bv <= tol_v:
            return 2, ts
    return 0, ts


@numba.njit(cache=True)
def locked2_quick(beta, gamma, omega, d, wl2, g0):
    """q2 of :func:`locked_quick_reject`: ω²G₀ cos d / 6 where L6 applies, else 0."""
    if not (wl2 - 0.25 * beta * beta > 0.0):
        return 0.0
    return omega * omega * g0 * math.cos(d) / 6.0


@numba.njit(cache=True)
def locked_coef(beta, wl2, theta_star, theta, v, gamma=0.0, order=1):
    """The locked window's coefficient vector anchored at (θ, θ').

    Parameters
    ----------
    beta, wl2 : float
        β and ω_l².
    theta_star : float
        The equilibrium (from :func:`locked_bound`).
    theta, v : float
        The anchor state.
    gamma : float, optional
        γ (the second order's forcing γx²/2; unused at order 1).
    order : int, optional
        1 (L2) or 2 (L6, under-damped only: :func:`locked_choice` says which).

    Returns
    -------
    ndarray, shape (LOCKED_WIDTH,) or (LOCKED2_WIDTH,)
        [LOCKED_TAG, θ₀, x₀, v₀, β/2, s², ω_l²], at order 2 followed by
        [2, Q_r, Q_i, M, D_r, D_i] (see LOCKED_TAG).
    """
    c = np.empty(LOCKED2_WIDTH if order == 2 else LOCKED_WIDTH)
    c[0] = LOCKED_TAG
    c[1] = theta
    c[2] = theta - theta_star
    c[3] = v
    c[4] = 0.5 * beta
    c[5] = wl2 - 0.25 * beta * beta
    c[6] = wl2
    if order == 2:
        qr, qi, m, dr, di, _, _ = locked2_terms(beta, gamma, wl2, c[2], v)
        c[7], c[8], c[9], c[10], c[11], c[12] = 2.0, qr, qi, m, dr, di
    return c


@numba.njit(cache=True, inline="always")
def locked_eval(coef, t):
    """The linearized motion of a locked window (item L2; with L6's x₂ at order 2).

    Parameters
    ----------
    coef : ndarray
        From :func:`locked_coef`.
    t : float
        Time from the anchor (≥ 0; any size: the exponentials only decay).

    Returns
    -------
    theta, v : float
        θ and θ' (at t = 0 the anchor, bit for bit).
    """
    th0, x0, v0, hb, s2, wl2 = coef[1], coef[2], coef[3], coef[4], coef[5], coef[6]
    b = v0 + hb * x0
    s = e = c1 = s1 = 0.0
    if s2 > 0.0:
        s = math.sqrt(s2)
        e = math.exp(-hb * t)
        c1 = math.cos(s * t)
        s1 = math.sin(s * t)
        ec = e * c1
        es = e * s1 / s
    elif s2 < 0.0:
        mu = math.sqrt(-s2)
        lam1 = -wl2 / (hb + mu)
        e1 = math.exp(lam1 * t)
        ec = 0.5 * (e1 + math.exp((-hb - mu) * t))
        es = e1 * (-math.expm1(-2.0 * mu * t)) / (2.0 * mu)
    else:
        e = math.exp(-hb * t)
        ec = e
        es = e * t
    x = x0 * ec + b * es
    xd = x0 * (-hb * ec - s2 * es) + b * (ec - hb * es)
    if coef.size >= LOCKED2_WIDTH and coef[7] == 2.0 and t != 0.0 and s2 > 0.0:
        # (L6): x₂ and x₂' (zero at the anchor by construction, skipped there so
        # that t = 0 is the anchor bit for bit).
        qr, qi, m, dr, di = coef[8], coef[9], coef[10], coef[11], coef[12]
        e2 = e * e
        c2 = c1 * c1 - s1 * s1
        sn2 = 2.0 * s1 * c1
        beta = 2.0 * hb
        x = x + (e2 * (qr * c2 - qi * sn2) + m * e2 + e * (dr * c1 - di * s1))
        xd = xd + (e2 * ((-beta * qr - 2.0 * s * qi) * c2 - (-beta * qi + 2.0 * s * qr) * sn2) - beta * m * e2
                   + e * ((-hb * dr - s * di) * c1 - (-hb * di + s * dr) * s1))
    return th0 + (x - x0), xd


@numba.njit(cache=True, inline="always")
def cycle_switch(dv, dv_prev, dT, v, theta, vmax, amax, n_rest, rtol, atol):
    """Whether the return map has converged enough to switch to the cycle (item R2).

    Parameters
    ----------
    dv, dv_prev : float
        The last two changes of θ' between successive crossings.
    dT : float
        The last change of the return time.
    v, theta : float
        θ', θ at the last crossing.
    vmax : float
        Largest |θ'| seen over the last period.
    amax : float
        A bound on |θ''| (|γ| + β·vmax + ω²).
    n_rest : float
        Periods left to the end of the span.
    rtol, atol : float
        The run's tolerances.

    Returns
    -------
    bool
    """
    if dv_prev == 0.0:
        return dv == 0.0 and dT == 0.0
    mu = abs(dv) / abs(dv_prev)
    if not (mu <= CYCLE_MAX_MULTIPLIER):
        return False
    tail = 1.0 / (1.0 - mu)
    # (R2): the period's distance to the cycle's, |dT|·tail, repeats every remaining period.
    drift = n_rest * abs(dT) * tail
    scale_v = SWITCH_SAFETY * (atol + rtol * abs(v))
    return (abs(dv) * tail <= scale_v and drift * amax <= scale_v
            and drift * vmax <= SWITCH_SAFETY * (atol + rtol * abs(theta)))


@numba.njit(cache=True)
def cycle_coef(theta_c, v_c, period, t_off, beta, gamma, omega, rtol, atol, sign, karg, error_order,
               wind_c, period_lo):
    """A running-cycle window's coefficient vector (layout: CYCLE_TAG; item R3).

    Parameters
    ----------
    theta_c, v_c : float
        The cycle's anchor: the crossing of θ = θ_c with speed v_c.
    period : float
        T_c.
    t_off : float
        Time from the anchor crossing to the window's start.
    beta, gamma, omega, rtol, atol : float
        The model and the tolerances the stored period is re-taken with.
    sign : float
        +1 or −1: θ advances by 2π·sign per period.
    karg, error_order : int
        The approximant's kind argument and error order.
    wind_c : float
        Winding count of the anchor: it lies at θ = 2π·wind_c + θ_c.
    period_lo : float
        Low part of the period: T_c + period_lo is the period in double-double (0 for
        the running cycle's averaged period; C3).

    Returns
    -------
    ndarray, shape (CYCLE_WIDTH,)
    """
    c = np.empty(CYCLE_WIDTH)
    c[0] = CYCLE_TAG
    c[1] = theta_c
    c[2] = v_c
    c[3] = period
    c[4] = t_off
    c[5] = beta
    c[6] = gamma
    c[7] = omega
    c[8] = rtol
    c[9] = atol
    c[10] = sign
    c[11] = karg
    c[12] = error_order
    c[13] = wind_c
    c[14] = period_lo
    return c


@numba.njit(cache=True)
def locked_eval_array(coef, t, out_theta, out_v):
    """:func:`locked_eval` at each of ``t``.

    Parameters
    ----------
    coef : ndarray
        From :func:`locked_coef`.
    t : ndarray
        Times from the anchor.
    out_theta, out_v : ndarray
        Filled with θ, θ' (same shape as ``t``).
    """
    for i in range(t.size):
        a, b = locked_eval(coef, t[i])
        out_theta[i] = a
        out_v[i] = b


def cycle_summary(regime, period, sign):
    """``(period, mean_velocity)`` of a result: T_c and ⟨θ'⟩ = ±2π/T_c when the run
    switched to the running cycle, (T, 0) when it switched to a libration, (nan, 0) when
    it switched to the locked state, else (nan, nan).

    Parameters
    ----------
    regime : int
        The run record's ``regime``.
    period, sign : float
        Its ``cyc_T`` and ``cyc_sign``.

    Returns
    -------
    (float, float)
    """
    if regime == REGIME_LOCKED:
        return math.nan, 0.0  # at rest at the equilibrium: no net motion
    if regime == REGIME_LIBRATION:
        return float(period), 0.0  # a closed orbit: no net motion
    if regime != REGIME_RUNNING:
        return math.nan, math.nan
    return float(period), float(sign) * 2.0 * math.pi / float(period)


# ---------------------------------------------------------------------------
# Libration (β = 0; items C1-C4)
# ---------------------------------------------------------------------------


@numba.njit(cache=True)
def _dd_potential(w2h, w2l, cdh, cdl, eh, el, gamma, xh, xl):
    # (C1): U(x) = 2ω² cos d sin²(x/2) + (ω² sin d − γ) sin x − γ(x − sin x) in
    # double-double; (w2h, w2l) = ω², (cdh, cdl) = cos d, (eh, el) = ω² sin d − γ.
    hh, hl = 0.5 * xh, 0.5 * xl
    sh, sl, ch, cl = dd_sincos_any(hh, hl)
    s2h, s2l = dd_mul(sh, sl, sh, sl)
    sxh, sxl = dd_mul(sh, sl, ch, cl)
    sxh, sxl = 2.0 * sxh, 2.0 * sxl  # sin x = 2 sin(x/2) cos(x/2)
    if abs(xh) < X_MINUS_SIN_SERIES:
        # x − sin x = Σ_{n≥1} (−1)^(n+1) x^(2n+1)/(2n+1)!
        x2h, x2l = dd_mul(xh, xl, xh, xl)
        th, tl = dd_mul(x2h, x2l, xh, xl)
        th, tl = dd_div_d(th, tl, 6.0)
        mh, ml = th, tl
        for n in range(2, DD_X_MINUS_SIN_TERMS + 2):
            th, tl = dd_mul(th, tl, x2h, x2l)
            th, tl = dd_div_d(th, tl, -float((2 * n) * (2 * n + 1)))
            mh, ml = dd_add(mh, ml, th, tl)
    else:
        mh, ml = dd_add(xh, xl, -sxh, -sxl)
    ah, al = dd_mul(w2h, w2l, cdh, cdl)
    ah, al = dd_mul(2.0 * ah, 2.0 * al, s2h, s2l)
    bh, bl = dd_mul(eh, el, sxh, sxl)
    gh, gl = dd_mul_d(mh, ml, gamma)
    uh, ul = dd_add(ah, al, bh, bl)
    return dd_add(uh, ul, -gh, -gl)


@numba.njit(cache=True)
def _turning_point(w2, gamma, d, h0, edge):
    # (C1): the root of U(x) = H' between 0 and the saddle ``edge`` (U rises from 0 to
    # above H' there), bracketed Newton in double.
    lo, hi = 0.0, edge
    x = 0.5 * edge
    for _ in range(LIBRATION_NEWTON_STEPS):
        f = _potential(w2, gamma, d, x) - h0
        if f == 0.0:
            return x
        if f < 0.0:
            lo = x
        else:
            hi = x
        du = w2 * math.sin(d + x) - gamma
        x_new = x - f / du if du != 0.0 else 0.5 * (lo + hi)
        if not (min(lo, hi) < x_new < max(lo, hi)):
            x_new = 0.5 * (lo + hi)
        if x_new == x:
            break
        x = x_new
    return x


@numba.njit(cache=True)
def libration_period(gamma, omega, theta, v):
    """The period of the conservative libration through (θ, θ') (items C1, C2).

    Parameters
    ----------
    gamma, omega : float
        The model's torque and ω > 0 (β = 0).
    theta, v : float
        The state.

    Returns
    -------
    t_hi, t_lo : float
        The period T = t_hi + t_lo in double-double; nan, nan where the state is not
        trapped in a well, its amplitude is below LIBRATION_MIN_AMPLITUDE, or the
        quadrature did not converge by LIBRATION_NODES_MAX nodes.
    dt : float
        δT ≥ |t_hi + t_lo − T| (C2).
    v_max : float
        The largest |θ'| on the orbit.
    x_span : float
        x₊ − x₋: θ stays within this of the given θ.
    """
    nan = math.nan
    w2 = omega * omega
    if not (abs(gamma) < w2):
        return nan, nan, nan, nan, nan
    d = math.asin(gamma / w2)
    # (C1): the angle in the well of d, in double-double.
    _j, ph, pl = reduce_2pi(theta)
    if ph > math.pi - d:
        ph, pl = dd_add(ph, pl, -TWO_PI_HI, -TWO_PI_LO)
    elif ph <= -math.pi - d:
        ph, pl = dd_add(ph, pl, TWO_PI_HI, TWO_PI_LO)
    x0h, x0l = dd_add(ph, pl, -d, 0.0)
    xr = math.pi - 2.0 * d
    xl = -math.pi - 2.0 * d
    ur = _potential(w2, gamma, d, xr)
    ul = _potential(w2, gamma, d, xl)
    h0 = 0.5 * v * v + _potential(w2, gamma, d, x0h)
    barrier = min(ur, ul)
    if not (xl < x0h < xr) or not (h0 < barrier - LIBRATION_BARRIER_MARGIN * w2):
        return nan, nan, nan, nan, nan
    # Constants of U in double-double.
    w2h, w2l = two_prod(omega, omega)
    sdh, sdl, cdh, cdl = dd_sincos(d, 0.0)
    eh, el = dd_mul(w2h, w2l, sdh, sdl)
    eh, el = dd_add(eh, el, -gamma, 0.0)
    # H' = v²/2 + U(x₀).
    vh, vl = two_prod(v, v)
    uh, ul2 = _dd_potential(w2h, w2l, cdh, cdl, eh, el, gamma, x0h, x0l)
    hh, hl = dd_add(0.5 * vh, 0.5 * vl, uh, ul2)
    if not (hh > 0.0):
        return nan, nan, nan, nan, nan
    # (C1): turning points, double then double-double Newton on F = H' − U.
    tp = np.empty(4)
    for side in range(2):
        edge = xr if side == 0 else xl
        xh_ = _turning_point(w2, gamma, d, hh, edge)
        xl_ = 0.0
        for _ in range(LIBRATION_DD_NEWTON):
            uh, ul2 = _dd_potential(w2h, w2l, cdh, cdl, eh, el, gamma, xh_, xl_)
            fh, fl = dd_add(hh, hl, -uh, -ul2)
            du = w2 * math.sin(d + xh_) - gamma
            if du == 0.0:
                return nan, nan, nan, nan, nan
            xh_, xl_ = dd_add(xh_, xl_, fh / du, 0.0)
        tp[2 * side] = xh_
        tp[2 * side + 1] = xl_
    mh, ml = dd_add(tp[0], tp[1], tp[2], tp[3])
    mh, ml = 0.5 * mh, 0.5 * ml
    rh, rl = dd_add(tp[0], tp[1], -tp[2], -tp[3])
    rh, rl = 0.5 * rh, 0.5 * rl
    if not (rh >= LIBRATION_MIN_AMPLITUDE):
        return nan, nan, nan, nan, nan
    # (C2): the midpoint rule, M doubled until two successive sums agree.
    prev_h, prev_l = nan, 0.0
    m_nodes = LIBRATION_NODES_MIN
    while m_nodes <= LIBRATION_NODES_MAX:
        sh_, sl_ = 0.0, 0.0
        for j in range(m_nodes):
            # ψ_j = −π/2 + (j + ½)π/M ((j + ½)/M is exact: M is a power of 2).
            qh, ql = dd_mul_d(PI_HI, PI_LO, (j + 0.5) / m_nodes)
            qh, ql = dd_add(qh, ql, -PIO2_HI, -PIO2_LO)
            snh, snl, csh, csl = dd_sincos(qh, ql)
            xh_, xl_ = dd_mul(rh, rl, snh, snl)
            xh_, xl_ = dd_add(mh, ml, xh_, xl_)
            uh, ul2 = _dd_potential(w2h, w2l, cdh, cdl, eh, el, gamma, xh_, xl_)
            fh, fl = dd_add(hh, hl, -uh, -ul2)
            if not (fh > 0.0):
                return nan, nan, nan, nan, nan
            qh, ql = dd_sqrt(2.0 * fh, 2.0 * fl)
            gh, gl = dd_mul(rh, rl, csh, csl)
            gh, gl = dd_div(gh, gl, qh, ql)
            sh_, sl_ = dd_add(sh_, sl_, gh, gl)
        # T_M = (2π/M) Σ g.
        th, tl = dd_mul_d(TWO_PI_HI, TWO_PI_LO, 1.0 / m_nodes)
        th, tl = dd_mul(th, tl, sh_, sl_)
        diff = abs((th - prev_h) + (tl - prev_l))
        if diff <= LIBRATION_QUAD_RTOL * th:
            return th, tl, diff + LIBRATION_DD_FLOOR * th, math.sqrt(2.0 * hh), 2.0 * rh
        prev_h, prev_l = th, tl
        m_nodes *= 2
    return nan, nan, nan, nan, nan


# ---------------------------------------------------------------------------
# Phase-locked to the drive (S1-S7)
# ---------------------------------------------------------------------------


@numba.njit(cache=True)
def strobe_period(freq, q):
    """The period qT_d = 2πq/Ω as a double-double (items S1, S6).

    Parameters
    ----------
    freq : float
        Ω > 0.
    q : float
        Drive periods per period of the orbit (an integer, 1 to STROBE_MAX_PERIODS: S7).

    Returns
    -------
    hi, lo : float
    """
    hi, lo = dd_div_d(TWO_PI_HI, TWO_PI_LO, freq)
    return dd_mul_d(hi, lo, q)


@numba.njit(cache=True)
def strobe_time(t_s, n, p_hi, p_lo):
    """The stroboscopic time t_s + n·P (item S1): its rounding and the residual.

    Parameters
    ----------
    t_s : float
        The first sample's time (the run's start).
    n : float
        Sample index (an integer).
    p_hi, p_lo : float
        P (:func:`strobe_period`).

    Returns
    -------
    t_n, r_n : float
        t_n = fl(t_s + nP) and r_n = (t_s + nP) − t_n (to double-double accuracy).
    """
    mh, ml = dd_mul_d(p_hi, p_lo, n)
    return dd_add(mh, ml, t_s, 0.0)


@numba.njit(cache=True)
def strobe_phase(freq, phase, t):
    """The drive's phase Ωt + φ reduced to [−π, π] (item S6).

    Ωt is an exact product and the reduction is :func:`mbm.special.dd.reduce_2pi`'s, so
    the result is good to a few ulps of π for any t (|Ωt| < 1e15).

    Parameters
    ----------
    freq, phase : float
        The drive's Ω and φ.
    t : float
        Time.

    Returns
    -------
    float
    """
    p, e = two_prod(freq, t)
    hi, e2 = two_sum(p, phase)
    _, rh, rl = reduce_2pi(hi)
    return rh + (rl + (e + e2))


@numba.njit(cache=True)
def strobe_split(t, t_a, p_hi, p_lo):
    """``(n, s)`` with t − t_a = nP + s, 0 ≤ s ≤ fl(P) (item S6).

    t − t_a is formed exactly (Knuth's sum) and nP in double-double, so s carries a few
    ulps of P whatever n (not n·eps·P).

    Parameters
    ----------
    t, t_a : float
        The time and the anchor's time.
    p_hi, p_lo : float
        P (:func:`strobe_period`).

    Returns
    -------
    n, s : float
        n an integer (as a float).
    """
    th, tl = two_sum(t, -t_a)
    n = np.floor(th / p_hi)
    sh, sl = 0.0, 0.0
    for _ in range(3):
        mh, ml = dd_mul_d(p_hi, p_lo, n)
        sh, sl = dd_add(th, tl, -mh, -ml)
        # The quotient's rounding can put s just outside [0, P) (compared in
        # double-double: s may round to fl(P) while below P): one period more or less.
        if sh < 0.0 or (sh == 0.0 and sl < 0.0):
            n -= 1.0
        elif sh > p_hi or (sh == p_hi and sl >= p_lo):
            n += 1.0
        else:
            break
    return n, min(max(sh + sl, 0.0), p_hi)


@numba.njit(cache=True, inline="always")
def _spectral_radius(tau, det):
    # (S4): max |μ| of μ² − τμ + D = 0.
    disc = tau * tau - 4.0 * det
    return math.sqrt(det) if disc < 0.0 else 0.5 * (abs(tau) + math.sqrt(disc))


@numba.njit(cache=True)
def strobe_switch(d3t, d3v, d2t, d2v, d1t, d1v, ct, cv, det, omega, scale, tau1, tau2, rho_clean):
    """Whether the stroboscopic deviations have converged enough to switch (items S3-S5).

    Parameters
    ----------
    d3t, d3v, d2t, d2v, d1t, d1v, ct, cv : float
        The last four deviations Δ (θ and θ' parts), oldest first (ct, cv the newest).
    det : float
        D = e^{−βP} (S2).
    omega : float
        ω: the θ parts are weighted by it.
    scale : float
        SWITCH_SAFETY · min(atol + rtol·|θ'|, ω(atol + rtol·|θ|)) at the anchor (S5).
    tau1, tau2 : float
        The traces fitted at the two samples before (nan where that fit failed or was
        not made).
    rho_clean : float
        The spectral radius of the last clean fit (residual ≤ STROBE_CLEAN_RESIDUAL;
        nan: none yet).

    Returns
    -------
    ok : bool
        A clean fit seen, the three fits (this one, tau1, tau2) within
        STROBE_FIT_RESIDUAL and within STROBE_TRACE_AGREE of each other,
        ρ ≤ STROBE_MAX_MULTIPLIER and B ≤ scale.
    tau : float
        This sample's fitted trace (nan where the fit failed).
    rho_clean : float
        Updated: this fit's spectral radius if it is clean, else the one given.
    rho, bound : float
        The spectral radius used and B (S3); inf where a fit failed.
    """
    # Scaled to the largest component (the squares below neither underflow nor overflow).
    big = max(max(max(omega * abs(d3t), abs(d3v)), max(omega * abs(d2t), abs(d2v))),
              max(max(omega * abs(d1t), abs(d1v)), max(omega * abs(ct), abs(cv))))
    if big == 0.0:
        # Converged to the bit: every later deviation is 0.
        return True, math.nan, rho_clean, 0.0, 0.0
    if not (big < math.inf):
        return False, math.nan, rho_clean, math.inf, math.inf
    w = omega / big
    u = 1.0 / big
    # (S4): the equations x₂ + D·x₀ = τ·x₁ of the triples (d3, d2, d1) and (d2, d1, c).
    a0, a1, a2, a3 = w * d2t, u * d2v, w * d1t, u * d1v
    b0 = w * (d1t + det * d3t)
    b1 = u * (d1v + det * d3v)
    b2 = w * (ct + det * d2t)
    b3 = u * (cv + det * d2v)
    x1 = big * math.sqrt((w * ct) ** 2 + (u * cv) ** 2)
    x0 = big * math.sqrt(a2 * a2 + a3 * a3)
    s11 = a0 * a0 + a1 * a1 + a2 * a2 + a3 * a3
    if s11 == 0.0:
        # d2 = d1 = 0: converged to the bit if the newest is 0 too.
        return x1 == 0.0, math.nan, rho_clean, 0.0, 0.0
    tau = (a0 * b0 + a1 * b1 + a2 * b2 + a3 * b3) / s11
    res = math.sqrt((b0 - tau * a0) ** 2 + (b1 - tau * a1) ** 2 + (b2 - tau * a2) ** 2
                    + (b3 - tau * a3) ** 2)
    res_rel = res / math.sqrt(s11)
    if not (res_rel <= STROBE_FIT_RESIDUAL):
        return False, math.nan, rho_clean, math.inf, math.inf
    # (S4): ρ of this fit, at |τ| widened by the residual's share of τ (ρ does not
    # decrease as |τ| grows); a clean fit's is remembered, for fits at the noise floor.
    rho = _spectral_radius(abs(tau) + STROBE_NOISE_WIDEN * res_rel * (1.0 + abs(tau)), det)
    if res_rel <= STROBE_CLEAN_RESIDUAL:
        rho_clean = rho
    if math.isnan(tau1) or math.isnan(tau2) or math.isnan(rho_clean):
        return False, tau, rho_clean, math.inf, math.inf
    # (S4): three successive fits agreeing (noise passes one fit now and then, with a
    # wrong τ, but not three that agree), ρ at the largest |τ| of them widened by their
    # spread, and not below the last clean fit's.
    lo = min(tau, min(tau1, tau2))
    hi = max(tau, max(tau1, tau2))
    if not (hi - lo <= STROBE_TRACE_AGREE):
        return False, tau, rho_clean, math.inf, math.inf
    tau_wide = (max(abs(tau), max(abs(tau1), abs(tau2))) + (hi - lo)
                + STROBE_NOISE_WIDEN * res_rel * (1.0 + abs(tau)))
    rho = max(_spectral_radius(tau_wide, det), rho_clean)
    if not (rho <= STROBE_MAX_MULTIPLIER):
        return False, tau, rho_clean, rho, math.inf
    # (S3): the tail of the deviations still to come.
    g = 1.0 / ((1.0 - rho) * (1.0 - rho))
    bound = x1 * (g - 1.0) + det * x0 * g
    return bound <= scale, tau, rho_clean, rho, bound


@numba.njit(cache=True)
def strobe_coef(phi_a, v_a, k_a, t_a, q, p, psi_a, beta, gamma, omega, amp, freq, rtol, atol, karg,
                error_order):
    """A phase-locked window's coefficient vector (layout: STROBE_TAG; item S6).

    Parameters
    ----------
    phi_a, v_a, k_a : float
        The anchor: θ = 2πk_a + φ_a, θ'_a.
    t_a : float
        Its time (a stroboscopic sample's).
    q, p : float
        Drive periods per period (1 to STROBE_MAX_PERIODS, S7) and turns per period.
    psi_a : float
        :func:`strobe_phase` at t_a.
    beta, gamma, omega, amp, freq : float
        The model and the drive's A, Ω.
    rtol, atol : float
        The tolerances the stored period is re-taken with.
    karg, error_order : int
        The approximant's kind argument and error order.

    Returns
    -------
    ndarray, shape (STROBE_WIDTH,)
    """
    c = np.empty(STROBE_WIDTH)
    c[0] = STROBE_TAG
    c[1] = phi_a
    c[2] = v_a
    c[3] = k_a
    c[4] = t_a
    c[5] = q
    c[6] = p
    c[7] = psi_a
    c[8] = beta
    c[9] = gamma
    c[10] = omega
    c[11] = amp
    c[12] = freq
    c[13] = rtol
    c[14] = atol
    c[15] = karg + STROBE_CODE * error_order
    return c


def strobe_summary(p, q, freq):
    """``(period, mean_velocity)`` of a phase-locked run: qT_d and pΩ/q (item S6).

    Parameters
    ----------
    p, q : float
        Turns per period and drive periods per period (the record's ``str_p``, ``str_q``).
    freq : float
        Ω.

    Returns
    -------
    (float, float)
    """
    return float(q) * 2.0 * math.pi / float(freq), float(p) * float(freq) / float(q)
