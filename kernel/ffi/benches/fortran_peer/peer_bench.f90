! Times stoss's kernel, called as an Abaqus/Explicit VUMAT through the C ABI
! (stoss_abaqus_vumat), beside a plain hand-written Johnson-Cook VUMAT (jc_vumat_peer.f90) on
! the same problem, in one process, alternately (issue 14's side-by-side measurement):
!   4340 steel (Johnson & Cook 1985 constants, G 81.8 GPa, K 159 GPa, rho 7830, c_p 477,
!   chi 0.9), blocks of 128 points, uniaxial compressive strain -1e-5 per step of 1e-8 s
!   (1e3 /s), every step plastic: 800 steps of warm-up (developed flow) then 1000 timed steps.
! Each round times both codes once; the figure reported is the median over the rounds, in
! nanoseconds per point-update. The peer runs at two residual tolerances, relative to the
! trial stress: 1e-6 (a typical hand-written stop) and 1e-12 (closer to stoss's return,
! whose residual is below 1e-14 of the trial stress).
!
! Usage: peer_bench [rounds]   (default 9)
module stoss_vumat_abi
  use, intrinsic :: iso_c_binding
  implicit none
  interface
    function stoss_material_block_size() bind(C, name="stoss_material_block_size") result(size)
      import :: c_int32_t
      integer(c_int32_t) :: size
    end function stoss_material_block_size
    function stoss_material_defaults_4340(block) bind(C, name="stoss_material_defaults_4340") &
        result(code)
      import :: c_ptr, c_int32_t
      type(c_ptr), value :: block
      integer(c_int32_t) :: code
    end function stoss_material_defaults_4340
    function stoss_material_to_card(block, card, capacity, length, message, message_capacity) &
        bind(C, name="stoss_material_to_card") result(code)
      import :: c_ptr, c_double, c_size_t, c_char, c_int32_t
      type(c_ptr), value :: block
      real(c_double), intent(out) :: card(*)
      integer(c_size_t), value :: capacity
      integer(c_size_t), intent(out) :: length
      character(kind=c_char), intent(out) :: message(*)
      integer(c_size_t), value :: message_capacity
      integer(c_int32_t) :: code
    end function stoss_material_to_card
    function stoss_abaqus_vumat(props, nprops, nblock, ndir, nshr, nstatev, step_time, &
                                total_time, dt, strain_inc, stress_old, state_old, &
                                ener_intern_old, stress_new, state_new, ener_intern_new, &
                                wave_speed, status, first_failure, message, message_capacity) &
        bind(C, name="stoss_abaqus_vumat") result(code)
      import :: c_double, c_size_t, c_int32_t, c_char
      real(c_double), intent(in) :: props(*)
      integer(c_size_t), value :: nprops, nblock, ndir, nshr, nstatev
      real(c_double), value :: step_time, total_time, dt
      real(c_double), intent(in) :: strain_inc(*), stress_old(*), state_old(*)
      real(c_double), intent(in) :: ener_intern_old(*)
      real(c_double), intent(out) :: stress_new(*), state_new(*), ener_intern_new(*)
      real(c_double), intent(out) :: wave_speed(*)
      integer(c_int32_t), intent(out) :: status(*)
      integer(c_size_t), intent(out) :: first_failure
      character(kind=c_char), intent(out) :: message(*)
      integer(c_size_t), value :: message_capacity
      integer(c_int32_t) :: code
    end function stoss_abaqus_vumat
  end interface
end module stoss_vumat_abi

module peer_bench_support
  use, intrinsic :: iso_fortran_env, only: real64, int64
  implicit none
  integer, parameter :: nblock = 128, nstatev = 8, warm_steps = 800, timed_steps = 1000
  real(real64), parameter :: dt = 1.0e-8_real64, axial = -1.0e-5_real64
contains
  ! Median of a small array (insertion sort of a copy).
  real(real64) function median(values)
    real(real64), intent(in) :: values(:)
    real(real64) :: sorted(size(values)), x
    integer :: i, j
    sorted = values
    do i = 2, size(sorted)
      x = sorted(i)
      j = i - 1
      do while (j >= 1)
        if (sorted(j) <= x) exit
        sorted(j + 1) = sorted(j)
        j = j - 1
      end do
      sorted(j + 1) = x
    end do
    median = sorted((size(sorted) + 1) / 2)
  end function median

  real(real64) function seconds()
    integer(int64) :: count, rate
    call system_clock(count, rate)
    seconds = real(count, real64) / real(rate, real64)
  end function seconds
end module peer_bench_support

program peer_bench
  use, intrinsic :: iso_c_binding
  use, intrinsic :: iso_fortran_env, only: real64, int64
  use stoss_vumat_abi
  use peer_bench_support
  implicit none
  integer(c_int64_t), allocatable, target :: block(:)
  real(c_double) :: card(128)
  integer(c_size_t) :: nprops, first_failure
  character(kind=c_char) :: message(256)
  integer(c_int32_t) :: code, status(nblock)
  real(real64) :: strain(nblock, 6), wave(nblock)
  real(real64) :: stress(nblock, 6, 2), state(nblock, nstatev, 2), ener(nblock, 2)
  real(real64) :: props(14), tolerances(2)
  real(real64), allocatable :: stoss_ns(:), peer_ns(:, :)
  real(real64) :: start, time, peer_stress(2), peer_temp(2)
  integer(int64) :: iterations, peer_iterations(2)
  integer :: rounds, round, step, old, new, t, nargs
  character(len=32) :: arg

  rounds = 9
  nargs = command_argument_count()
  if (nargs >= 1) then
    call get_command_argument(1, arg)
    read (arg, *) rounds
  end if
  allocate (stoss_ns(rounds), peer_ns(rounds, 2))

  ! stoss's 4340 card, from its own defaults (implicit rate, adiabatic heating chi 0.9).
  allocate (block((stoss_material_block_size() + 7) / 8))
  code = stoss_material_defaults_4340(c_loc(block))
  if (code /= 0) error stop 'stoss_material_defaults_4340 failed'
  code = stoss_material_to_card(c_loc(block), card, int(size(card), c_size_t), nprops, &
                                message, int(size(message), c_size_t))
  if (code /= 0) error stop 'stoss_material_to_card failed'
  ! The peer's constants: the same material.
  props = [81.8e9_real64, 159.0e9_real64, 7830.0_real64, 477.0_real64, 0.9_real64, &
           792.0e6_real64, 510.0e6_real64, 0.26_real64, 0.014_real64, 1.0_real64, &
           1.03_real64, 298.0_real64, 1793.0_real64, 0.0_real64]
  tolerances = [1.0e-6_real64, 1.0e-12_real64]

  strain = 0.0_real64
  strain(:, 1) = axial

  start = 0.0_real64
  do round = 1, rounds
    ! stoss: warm-up from the zero (initial) state, then the timed steps.
    stress = 0.0_real64; state = 0.0_real64; ener = 0.0_real64
    old = 1; new = 2
    do step = 1, warm_steps + timed_steps
      if (step == warm_steps + 1) start = seconds()
      code = stoss_abaqus_vumat(card, nprops, int(nblock, c_size_t), 3_c_size_t, 3_c_size_t, &
                                int(nstatev, c_size_t), step * dt, step * dt, dt, strain, &
                                stress(:, :, old), state(:, :, old), ener(:, old), &
                                stress(:, :, new), state(:, :, new), ener(:, new), wave, &
                                status, first_failure, message, int(size(message), c_size_t))
      if (code /= 0) error stop 'stoss_abaqus_vumat failed'
      old = 3 - old; new = 3 - new
    end do
    time = seconds() - start
    stoss_ns(round) = time / real(timed_steps * nblock, real64) * 1.0e9_real64
    if (round == 1) then
      write (*, '(a, es12.5, a, f9.3, a, f8.5)') 'stoss: axial stress ', stress(1, 1, old), &
        ' Pa, T ', state(1, 3, old), ' K, eps_p ', state(1, 1, old)
    end if

    do t = 1, 2
      props(14) = tolerances(t)
      stress = 0.0_real64; state = 0.0_real64; ener = 0.0_real64
      old = 1; new = 2
      iterations = 0
      do step = 1, warm_steps + timed_steps
        if (step == warm_steps + 1) then
          start = seconds()
          iterations = 0
        end if
        call vumat_jc_peer(nblock, nstatev, props, dt, strain, stress(:, :, old), &
                           state(:, :, old), ener(:, old), stress(:, :, new), &
                           state(:, :, new), ener(:, new), iterations)
        old = 3 - old; new = 3 - new
      end do
      time = seconds() - start
      peer_ns(round, t) = time / real(timed_steps * nblock, real64) * 1.0e9_real64
      peer_iterations(t) = iterations
      peer_stress(t) = stress(1, 1, old)
      peer_temp(t) = state(1, 2, old)
    end do
    if (round == 1) then
      do t = 1, 2
        write (*, '(a, es8.1, a, es12.5, a, f9.3, a, f6.3, a)') 'peer (tol ', tolerances(t), &
          '): axial stress ', peer_stress(t), ' Pa, T ', peer_temp(t), ' K, ', &
          real(peer_iterations(t), real64) / real(timed_steps * nblock, real64), &
          ' flow-stress evaluations per update'
      end do
    end if
  end do

  write (*, '(a, i0, a)') 'ns per plastic point-update, median of ', rounds, ' rounds:'
  write (*, '(a, f8.1)') '  stoss (stoss_abaqus_vumat)   ', median(stoss_ns)
  write (*, '(a, f8.1)') '  peer VUMAT, tol 1e-6         ', median(peer_ns(:, 1))
  write (*, '(a, f8.1)') '  peer VUMAT, tol 1e-12        ', median(peer_ns(:, 2))
  write (*, '(a, f6.2, a, f6.2)') '  peer / stoss: ', median(peer_ns(:, 1)) / median(stoss_ns), &
    ' (tol 1e-6), ', median(peer_ns(:, 2)) / median(stoss_ns)
end program peer_bench
