! Fortran link test of the stoss C ABI through ISO_C_BINDING, written the way an LS-DYNA user
! material is: a umat-style subroutine (umat_stoss: cm, eps, sig, hsv, dt1, failel, as in
! LS-DYNA's umat41) that calls stoss_lsdyna_umat for one integration point, driven by a small
! main program along a uniaxial-strain path and a simple-shear path (engineering shear strain
! increments, gamma = 2 eps, as LS-DYNA passes them).
!
! The material constants are typed into cm(1..96) exactly as a user types them on the
! *MAT_USER_DEFINED_MATERIAL_MODELS card (layout: docs/user-material.md).
!
! Each step's history goes to <dir>/<case>.hex as 20 hex bit patterns per line, the format of
! kernel/ffi/examples/reference_histories.rs; .ci/ffi.sh compares the files byte for byte.
!
! Usage: umat_driver <output directory>
module stoss_kernel_abi
  use, intrinsic :: iso_c_binding
  implicit none
  integer(c_int32_t), parameter :: STOSS_STATUS_OK = 0
  integer(c_int32_t), parameter :: STOSS_FAILED_ERODE = 2
  integer, parameter :: STOSS_HISTORY_COUNT = 8
  interface
    function stoss_lsdyna_umat(cm, lmc, nlq, dt, eps, sig, hsv, nhv, failel, wave_speed, &
                               status, first_failure, message, message_capacity) &
        bind(C, name="stoss_lsdyna_umat") result(code)
      import :: c_double, c_size_t, c_int32_t, c_char
      real(c_double), intent(in) :: cm(*)
      integer(c_size_t), value :: lmc, nlq
      real(c_double), value :: dt
      real(c_double), intent(in) :: eps(*)
      real(c_double), intent(inout) :: sig(*), hsv(*)
      integer(c_size_t), value :: nhv
      integer(c_int32_t), intent(out) :: failel(*)
      real(c_double), intent(out) :: wave_speed(*)
      integer(c_int32_t), intent(out) :: status(*)
      integer(c_size_t), intent(out) :: first_failure
      character(kind=c_char), intent(out) :: message(*)
      integer(c_size_t), value :: message_capacity
      integer(c_int32_t) :: code
    end function stoss_lsdyna_umat
  end interface
end module stoss_kernel_abi

! A umat in the LS-DYNA style: constants cm, strain increments eps (engineering shear),
! stress sig and history hsv updated in place, time step dt1, element failure flag failel.
! (The wave speed is returned as well; a real umat would hand it to the time-step estimate.)
subroutine umat_stoss(cm, lmc, eps, sig, hsv, nhv, dt1, failel, wave_speed)
  use stoss_kernel_abi
  implicit none
  integer, intent(in) :: lmc, nhv
  real(c_double), intent(in) :: cm(lmc), eps(6), dt1
  real(c_double), intent(inout) :: sig(6), hsv(nhv)
  logical, intent(out) :: failel
  real(c_double), intent(out) :: wave_speed
  integer(c_int32_t) :: code, fail(1), point_status(1)
  integer(c_size_t) :: first_failure
  real(c_double) :: speed(1)
  character(kind=c_char) :: message(256)
  integer :: i

  code = stoss_lsdyna_umat(cm, int(lmc, c_size_t), 1_c_size_t, dt1, eps, sig, hsv, &
                           int(nhv, c_size_t), fail, speed, point_status, first_failure, &
                           message, int(size(message), c_size_t))
  if (code /= STOSS_STATUS_OK) then
    write (*, '(a, i0, a)', advance='no') 'umat_stoss: stoss status ', code, ': '
    do i = 1, size(message)
      if (message(i) == c_null_char) exit
      write (*, '(a)', advance='no') message(i)
    end do
    write (*, *)
    error stop 1
  end if
  failel = iand(fail(1), STOSS_FAILED_ERODE) /= 0
  wave_speed = speed(1)
end subroutine umat_stoss

module hex_output
  use, intrinsic :: iso_c_binding
  use, intrinsic :: iso_fortran_env, only: int64
  implicit none
contains
  ! The 16 lower-case hex digits of the bit pattern of x.
  function hex(x) result(text)
    real(c_double), intent(in) :: x
    character(len=16) :: text
    character(len=16), parameter :: digits = '0123456789abcdef'
    integer(int64) :: pattern
    integer :: k, nibble
    pattern = transfer(x, pattern)
    do k = 1, 16
      nibble = int(ibits(pattern, 4 * (16 - k), 4))
      text(k:k) = digits(nibble + 1:nibble + 1)
    end do
  end function hex

  subroutine write_record(unit, values)
    integer, intent(in) :: unit
    real(c_double), intent(in) :: values(20)
    integer :: k
    do k = 1, 19
      write (unit, '(a, a)', advance='no') hex(values(k)), ' '
    end do
    write (unit, '(a)') hex(values(20))
  end subroutine write_record
end module hex_output

program umat_driver
  use, intrinsic :: iso_c_binding
  use hex_output
  implicit none
  integer, parameter :: lmc = 96, nhv = 10
  real(c_double) :: cm_tjc(lmc), cm_jc(lmc), cm_upturn(lmc), cm_rht(lmc), cm_kc(lmc)
  real(c_double) :: r
  character(len=1024) :: directory

  if (command_argument_count() /= 1) then
    write (*, '(a)') 'usage: umat_driver <output directory>'
    error stop 2
  end if
  call get_command_argument(1, directory)

  ! Two-rate Johnson-Cook (illustrative test constants) with Johnson-Cook failure of 4340.
  cm_tjc = 0.0d0
  cm_tjc(1:16) = [1.0d0, 7830.0d0, 81.8d9, 159.0d9, 477.0d0, 298.0d0, &  ! version rho G K cp T0
                  5.0d0, 1.0d0, 1.0d0, 2.0d0, 0.9d0, 0.0d0, 0.0d0, &     ! TJC implicit linear adiabatic chi
                  1.0d0, 0.0d0, 0.0d0]                                   ! flags: JC damage
  cm_tjc(17:24) = [0.05d0, 3.44d0, -2.12d0, 0.002d0, 0.61d0, 1.0d0, 298.0d0, 1793.0d0]
  cm_tjc(25:38) = [792.0d6, 510.0d6, 0.26d0, 100.0d6, 20.0d0, 50.0d6, 200.0d0, &
                   0.01d0, 0.01d0, 0.05d0, 1000.0d0, 1.03d0, 298.0d0, 1793.0d0]

  ! Johnson-Cook 4340 (Johnson & Cook 1985), no failure.
  cm_jc = 0.0d0
  cm_jc(1:16) = [1.0d0, 7830.0d0, 81.8d9, 159.0d9, 477.0d0, 298.0d0, &
                 1.0d0, 1.0d0, 1.0d0, 2.0d0, 0.9d0, 0.0d0, 0.0d0, &
                 0.0d0, 0.0d0, 0.0d0]
  cm_jc(25:32) = [792.0d6, 510.0d6, 0.26d0, 0.014d0, 1.03d0, 1.0d0, 298.0d0, 1793.0d0]

  ! JC 4340 as composed terms with the diagnosis' high-rate upturn: a card of layout
  ! version 2 (strength code 6 = composed; hardening 1 = power, rate 6 = log-upturn,
  ! thermal 2 = homologous power; then A B n Q1 c1 Q2 c2, C e0 beta e_up, m Tr Tm).
  cm_upturn = 0.0d0
  cm_upturn(1:16) = [2.0d0, 7830.0d0, 81.8d9, 159.0d9, 477.0d0, 298.0d0, &
                     6.0d0, 1.0d0, 1.0d0, 2.0d0, 0.9d0, 0.0d0, 0.0d0, &
                     0.0d0, 0.0d0, 0.0d0]
  cm_upturn(25:41) = [1.0d0, 6.0d0, 2.0d0, 792.0d6, 510.0d6, 0.26d0, 0.0d0, 0.0d0, &
                      0.0d0, 0.0d0, 0.014d0, 1.0d0, 0.08d0, 2.0d3, 1.03d0, 298.0d0, &
                      1793.0d0]

  ! RHT concrete, a card of layout version 3 (strength code 7, implicit, EoS 6 = P-alpha,
  ! isothermal): seed 001 table 4.4's 92 MPa HPC. P17..P20: tensile failure 1 (hydro tensile
  ! limit), meridian 2 (characteristic points), rate scaling 1 (seed equation), cap 1;
  ! P21..P40: fc FT* FS* A N Q2 BQ PREFACT TENSRAT COMPRAT B M alpha delta e0c e0t D1 D2
  ! EFMIN SHRATD; P42..P52: the P-alpha EoS (A1 A2 A3 B0 B1 T1 T2 alpha0 p_crush p_lock n).
  cm_rht = 0.0d0
  cm_rht(1:16) = [3.0d0, 2420.0d0, 18.0d9, 21.47d9, 880.0d0, 293.0d0, &
                  7.0d0, 1.0d0, 6.0d0, 1.0d0, 0.0d0, 0.0d0, 0.0d0, &
                  0.0d0, 0.0d0, 0.0d0]
  cm_rht(17:20) = [1.0d0, 2.0d0, 1.0d0, 1.0d0]
  cm_rht(21:40) = [92.0d6, 0.057d0, 0.30d0, 1.9d0, 0.6d0, 0.6805d0, 0.0105d0, 2.0d0, &
                   0.80d0, 0.75d0, 1.3d0, 0.65d0, 0.010d0, 0.013d0, 30.0d-6, 3.0d-6, &
                   0.04d0, 1.0d0, 0.01d0, 0.13d0]
  cm_rht(42:52) = [24.4d9, 39.58d9, 9.04d9, 1.22d0, 1.22d0, 24.4d9, 0.0d0, &
                   2750.0d0 / 2420.0d0, 2.0d0 / 3.0d0 * 92.0d6, 6.0d9, 3.0d0]

  ! K&C concrete, a card of layout version 5 (strength code 8, implicit, EoS 5 = tabulated
  ! compaction, isothermal): seed 001 chapter 5's 100 MPa HPC (KcMaterial::HPC_100MPA_FOI).
  ! P17..P20: rate 2 (CEB-FIP), crack band 0 and its two widths; P21..P28: the maximum,
  ! yield and residual surfaces (Malvar's 45.4 MPa set scaled by r = fc/45.4 MPa);
  ! P29..P33: the described scalars fc ft fbc/fc b1 b2; P42..P66: the tabulated EoS of table
  ! 5.2 (8 points of eps p K); P67..P91: the damage function of table 5.3 (12 points, the
  ! lambdas, then the etas).
  r = 100.0d6 / 45.4d6
  cm_kc = 0.0d0
  cm_kc(1:16) = [5.0d0, 2420.0d0, 44.0d9 / (2.0d0 * 1.16d0), 21.57d9, 880.0d0, 293.0d0, &
                 8.0d0, 1.0d0, 5.0d0, 1.0d0, 0.0d0, 0.0d0, 0.0d0, &
                 0.0d0, 0.0d0, 0.0d0]
  cm_kc(17:20) = [2.0d0, 0.0d0, 0.0d0, 0.0d0]
  cm_kc(21:28) = [13.42d6 * r, 0.4463d0, 0.00178d-6 / r, &
                  10.13d6 * r, 0.625d0, 0.005676d-6 / r, &
                  0.4417d0, 0.002608d-6 / r]
  cm_kc(29:33) = [100.0d6, 5.2d6, 1.15d0, 1.6d0, 1.35d0]
  cm_kc(42:66) = [8.0d0, &
                  0.0d0, 0.0d0, 21.57d9, 0.0006d0, 13.3d6, 21.57d9, &
                  0.0022d0, 33.3d6, 15.15d9, 0.0104d0, 90.0d6, 10.0d9, &
                  0.0289d0, 216.0d6, 18.0d9, 0.0510d0, 390.0d6, 21.0d9, &
                  0.0628d0, 565.0d6, 23.0d9, 0.0726d0, 737.0d6, 25.0d9]
  cm_kc(67:91) = [12.0d0, &
                  0.0d0, 5.5d-6, 1.4d-5, 2.9d-5, 5.1d-5, 8.2d-5, &
                  4.8d-4, 8.6d-4, 1.44d-3, 3.06d-3, 1.2d-2, 2.5d-2, &
                  0.0d0, 0.25d0, 0.55d0, 0.80d0, 0.95d0, 1.0d0, &
                  0.95d0, 0.71d0, 0.45d0, 0.25d0, 0.06d0, 0.0d0]

  call run_case(cm_tjc, 1, 0.25d0, 250, 1.0d4, 'umat_tjc_tension')
  call run_case(cm_jc, 4, 0.3d0, 300, 1.0d3, 'umat_jc_simple_shear')
  call run_case(cm_upturn, 1, 0.25d0, 250, 1.0d4, 'umat_jc_upturn_tension')
  call run_case(cm_rht, 1, -0.08d0, 200, 1.0d4, 'umat_rht_compression')
  call run_case(cm_kc, 1, -0.03d0, 200, 1.0d3, 'umat_kc_compression')
  write (*, '(a)') 'umat_driver: wrote 5 histories to '//trim(directory)

contains

  ! Drive one point: strain component `component` (1 = xx uniaxial strain, 4 = xy simple
  ! shear, given as tensor strain and passed to the umat as engineering gamma = 2 eps) from 0
  ! to final_strain in `steps` equal steps at rate `rate`.
  subroutine run_case(cm, component, final_strain, steps, rate, name)
    real(c_double), intent(in) :: cm(lmc), final_strain, rate
    integer, intent(in) :: component, steps
    character(len=*), intent(in) :: name
    real(c_double) :: eps(6), sig(6), hsv(nhv), total(6), values(20)
    real(c_double) :: increment, dt1, time, wave_speed
    logical :: failel
    integer :: step, unit

    open (newunit=unit, file=trim(directory)//'/'//name//'.hex', status='replace', &
          action='write')
    sig = 0.0d0
    hsv = 0.0d0     ! LS-DYNA zero-initialises history: stoss starts from its initial state
    hsv(9) = 5.0d0  ! a host variable beyond stoss's 8 must be left alone
    total = 0.0d0
    time = 0.0d0
    increment = final_strain / real(steps, c_double)
    dt1 = abs(increment) / rate
    do step = 1, steps
      eps = 0.0d0
      if (component <= 3) then
        eps(component) = increment
      else
        eps(component) = 2.0d0 * increment  ! engineering shear
      end if
      call umat_stoss(cm, lmc, eps, sig, hsv, nhv, dt1, failel, wave_speed)
      if (hsv(9) /= 5.0d0) error stop 'umat_driver: host history variable 9 was changed'
      time = time + dt1
      total(component) = total(component) + increment
      values(1) = time
      values(2:7) = total
      values(8:13) = sig
      values(14:17) = hsv(1:4)   ! eps_p, rate, T, D
      values(18) = hsv(6)        ! E per reference volume
      values(19) = wave_speed
      values(20) = hsv(8)        ! flags
      call write_record(unit, values)
    end do
    close (unit)
  end subroutine run_case
end program umat_driver
