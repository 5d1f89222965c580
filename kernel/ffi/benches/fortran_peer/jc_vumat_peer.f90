! A plain Johnson-Cook user material in the Abaqus/Explicit VUMAT style, written for stoss as
! the peer its kernel is timed against (issue 14): what an engineer who writes their own
! VUMAT typically has. It is not part of stoss and is not used by it.
!
! Per point: hypoelastic trial stress (2G on the deviator, K on the volume change), yield
! check against the flow stress stored at the end of the point's last plastic step (state
! slot 4, rate included, as most hand-written VUMATs do), and if plastic a Newton iteration
! on the plastic multiplier dl of
!     q_trial - 3G dl - (A + B (eps_p + dl)^n) (1 + C ln(dl / (dt e0))) (1 - T*^m) = 0
! (rate implicit in the step, temperature T_n fixed, Johnson & Cook 1983), started from the
! previous step's multiplier (halving instead of a step to dl <= 0) and stopped when the
! residual is below `tol` times q_trial; the flow stress is the one of the last evaluation.
! Radial return, adiabatic heating chi sigma_y dl / (rho c_p), internal energy per unit mass
! by the trapezoidal rule.
!
! props: G, K, rho, c_p, chi, A, B, n, C, e0, m, Tr, Tm, tol.
! State: 1 eps_p, 2 T, 3 plastic strain rate of the last step, 4 stored flow stress.
! A zero state starts at T = Tr with the flow stress A.
! iterations: flow-stress evaluations summed over the block (for the report).
subroutine vumat_jc_peer(nblock, nstatev, props, dt, strain_inc, stress_old, state_old, &
                         ener_old, stress_new, state_new, ener_new, iterations)
  use, intrinsic :: iso_fortran_env, only: real64, int64
  implicit none
  integer, intent(in) :: nblock, nstatev
  real(real64), intent(in) :: props(14), dt
  real(real64), intent(in) :: strain_inc(nblock, 6), stress_old(nblock, 6)
  real(real64), intent(in) :: state_old(nblock, nstatev), ener_old(nblock)
  real(real64), intent(out) :: stress_new(nblock, 6), state_new(nblock, nstatev)
  real(real64), intent(out) :: ener_new(nblock)
  integer(int64), intent(inout) :: iterations

  real(real64) :: g, bulk, rho, cp, chi, a, b, n, c, e0, m, tref, tmelt, tol
  real(real64) :: de(6), sold(6), strial(6), snew(6), trace, mean_old, mean_new, q
  real(real64) :: eps_p, temp, rate_old, flow_stored, theta, tstar, dl, ddl, ep, hard
  real(real64) :: dhard, rfac, drfac, flow, f, df, scale, work
  integer :: i, k, it

  g = props(1); bulk = props(2); rho = props(3); cp = props(4); chi = props(5)
  a = props(6); b = props(7); n = props(8); c = props(9); e0 = props(10)
  m = props(11); tref = props(12); tmelt = props(13); tol = props(14)

  do i = 1, nblock
    eps_p = state_old(i, 1)
    temp = state_old(i, 2)
    rate_old = state_old(i, 3)
    flow_stored = state_old(i, 4)
    if (temp <= 0.0_real64) temp = tref
    if (flow_stored <= 0.0_real64) flow_stored = a

    de = strain_inc(i, :)
    trace = de(1) + de(2) + de(3)
    mean_old = (stress_old(i, 1) + stress_old(i, 2) + stress_old(i, 3)) / 3.0_real64
    sold = stress_old(i, :)
    sold(1:3) = sold(1:3) - mean_old
    strial = sold + 2.0_real64 * g * de
    strial(1:3) = strial(1:3) - 2.0_real64 * g * trace / 3.0_real64
    mean_new = mean_old + bulk * trace
    q = sqrt(1.5_real64 * (strial(1)**2 + strial(2)**2 + strial(3)**2 &
                           + 2.0_real64 * (strial(4)**2 + strial(5)**2 + strial(6)**2)))

    dl = 0.0_real64
    flow = flow_stored
    if (q > flow_stored) then
      tstar = (temp - tref) / (tmelt - tref)
      theta = 1.0_real64
      if (tstar > 0.0_real64) theta = 1.0_real64 - tstar**m
      dl = rate_old * dt
      if (dl <= 0.0_real64) dl = (q - flow_stored) / (3.0_real64 * g)
      do it = 1, 50
        ep = eps_p + dl
        hard = a + b * ep**n
        dhard = n * b * ep**(n - 1.0_real64)
        if (dl > e0 * dt) then
          rfac = 1.0_real64 + c * log(dl / (e0 * dt))
          drfac = c / dl
        else
          rfac = 1.0_real64
          drfac = 0.0_real64
        end if
        flow = hard * rfac * theta
        f = q - 3.0_real64 * g * dl - flow
        iterations = iterations + 1
        if (abs(f) <= tol * q) exit
        df = -3.0_real64 * g - (dhard * rfac + hard * drfac) * theta
        ddl = -f / df
        if (dl + ddl <= 0.0_real64) ddl = -0.5_real64 * dl  ! stay at dl > 0 (eps^(n-1))
        dl = dl + ddl
      end do
      scale = 1.0_real64 - 3.0_real64 * g * dl / q
      snew = strial * scale
      temp = temp + chi * flow * dl / (rho * cp)
    else
      snew = strial
    end if

    do k = 1, 3
      stress_new(i, k) = snew(k) + mean_new
    end do
    do k = 4, 6
      stress_new(i, k) = snew(k)
    end do
    work = 0.0_real64
    do k = 1, 3
      work = work + 0.5_real64 * (stress_old(i, k) + stress_new(i, k)) * de(k)
    end do
    do k = 4, 6
      work = work + (stress_old(i, k) + stress_new(i, k)) * de(k)
    end do
    ener_new(i) = ener_old(i) + work / rho

    state_new(i, 1) = eps_p + dl
    state_new(i, 2) = temp
    state_new(i, 3) = dl / dt
    state_new(i, 4) = flow
    do k = 5, nstatev
      state_new(i, k) = state_old(i, k)
    end do
  end do
end subroutine vumat_jc_peer
