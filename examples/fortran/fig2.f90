! fig2.f90 - the paper's Fig. 2 scene through the Fortran module.
!
!   vi_fig2_fortran            prints the first impacts and a summary
!   vi_fig2_fortran FILE.csv   also writes every impact as the program's
!                              --impacts-csv does (k,t,vn,x_1,x_2,v_1,v_2)
!   vi_fig2_fortran FILE.csv duffing
!                              the same with a host force from Fortran: a
!                              cubic spring -0.5 x_2^3 on mass 2 (issue 13)
!
! N = 2 chain, m = k = 1, c = 0.1, x_s = 0.1, r = 0.7, a = (0.5, 0),
! Omega = 0.9, stop on mass 2, from rest, 100 forcing periods, Adams with
! rtol 1e-8 and atol 1e-10 (the defaults of the C program).
module fig2_callbacks
  use, intrinsic :: iso_c_binding
  use vibroimpact
  implicit none
  integer :: unit_csv = 0, count = 0, intervals = 0
  real(c_double) :: worst = 0
  logical :: csv = .false.
contains
  integer(c_int) function on_event(ev, user) bind(C)
    type(vi_event), intent(in) :: ev
    type(c_ptr), value :: user
    real(c_double), pointer :: x(:), v(:)
    on_event = merge(1, 0, c_associated(user))  ! no user data here: go on
    if (ev%kind /= VI_EVENT_IMPACT) return
    call c_f_pointer(ev%x, x, [ev%n])
    call c_f_pointer(ev%v_minus, v, [ev%n])
    if (count < 5) print '(a,i3,a,f14.10,a,f13.10,a,f13.10)', ' impact', count, &
        ':  t = ', ev%t, '  v_n = ', ev%vn, '  x_1 = ', x(1)
    if (csv) write(unit_csv, '(i0,6(",",es24.17))') count, ev%t, ev%vn, x, v
    count = count + 1
  end function
  ! ledger: the closure residual of every impact-free interval
  integer(c_int) function on_interval(iv, user) bind(C)
    type(vi_ledger_interval), intent(in) :: iv
    type(c_ptr), value :: user
    on_interval = merge(1, 0, c_associated(user))
    intervals = intervals + 1
    worst = max(worst, iv%residual)
  end function
  ! a nonlinear force from the host code: g = -0.5 x_2^3 on mass 2; a NaN
  ! state is reported as a failure (the run stops with VI_ERR_CALLBACK)
  integer(c_int) function cubic(t, n, x, v, g, user) bind(C)
    real(c_double), value :: t
    integer(c_int), value :: n
    real(c_double), intent(in) :: x(n), v(n)
    real(c_double), intent(out) :: g(n)
    type(c_ptr), value :: user
    g = 0
    g(2) = -0.5_c_double * x(2) * x(2) * x(2)
    cubic = merge(1, 0, c_associated(user) .or. t /= t .or. any(v /= v))
  end function
end module fig2_callbacks

program fig2
  use, intrinsic :: iso_c_binding
  use vibroimpact
  use fig2_callbacks
  implicit none
  real(c_double), parameter :: pi = 3.14159265358979323846_c_double
  real(c_double) :: mass(2) = 1, k(2) = 1, c(2) = 0.1_c_double
  real(c_double) :: M(2, 2), Cm(2, 2), Km(2, 2), t, x(2), v(2)
  real(c_double) :: a(2) = [0.5_c_double, 0.0_c_double], zero(2) = 0
  real(c_double) :: w(2) = [0.0_c_double, 1.0_c_double]
  real(c_double), pointer :: omega(:)
  type(c_ptr) :: model = c_null_ptr, sim = c_null_ptr
  integer(c_int) :: st
  character(len=512) :: path

  if (vi_version_number() /= VI_HEADER_VERSION) stop 'header and library versions differ'
  if (command_argument_count() >= 1) then
    call get_command_argument(1, path)
    open(newunit=unit_csv, file=trim(path), status='replace', action='write')
    csv = .true.
    write(unit_csv, '(a)') 'k,t,vn,x_1,x_2,v_1,v_2'
  end if

  st = vi_build_chain(2, mass, k, c, M, Cm, Km, 2)
  st = vi_model_create(2, model)
  if (st == VI_OK) st = vi_model_set_mass(model, M, 2)
  if (st == VI_OK) st = vi_model_set_damping(model, Cm, 2)
  if (st == VI_OK) st = vi_model_set_stiffness(model, Km, 2)
  if (st == VI_OK) st = vi_model_set_forcing(model, 0.9_c_double, a, zero, zero)
  if (st == VI_OK) st = vi_model_set_stop(model, w, 0.1_c_double, 0.7_c_double)
  if (st == VI_OK) st = vi_model_setup(model)
  if (st /= VI_OK) then
    print '(a)', 'model: '//vi_string(vi_strerror(st))//': '//vi_string(vi_model_errmsg(model))
    stop 1
  end if
  call c_f_pointer(vi_model_omega(model), omega, [2])
  print '(a,2f12.8)', ' natural frequencies:', omega

  st = vi_sim_create(model, sim)
  if (st == VI_OK) st = vi_sim_set_tolerances(sim, 1.0e-8_c_double, 1.0e-10_c_double)
  if (st == VI_OK) st = vi_sim_set_event_callback(sim, c_funloc(on_event), c_null_ptr, c_null_funptr)
  if (command_argument_count() >= 2) then
    call get_command_argument(2, path)
    if (trim(path) == 'duffing' .and. st == VI_OK) &
        st = vi_sim_set_force(sim, c_funloc(cubic), c_null_funptr, c_null_ptr, c_null_funptr)
  end if
  if (command_argument_count() == 0) then  ! the ledger changes CVODE's steps: not in the CSV run
    if (st == VI_OK) st = vi_sim_enable_ledger(sim, 1_c_int)
    if (st == VI_OK) st = vi_sim_set_ledger_callback(sim, c_funloc(on_interval), c_null_ptr, &
                                                          c_null_funptr)
  end if
  if (st == VI_OK) st = vi_sim_run(sim, 100 * 2 * pi / 0.9_c_double)
  if (st /= VI_OK) then
    print '(a)', 'run: '//vi_string(vi_strerror(st))//': '//vi_string(vi_sim_errmsg(sim))
    stop 1
  end if
  st = vi_sim_state(sim, t, x, v)
  print '(a,i0,a,f10.4,a,i0,a)', ' ', count, ' impacts up to t = ', t, ' (', &
      vi_sim_stat(sim, VI_STAT_STEPS), ' steps)'
  if (intervals > 0) print '(a,i0,a,es9.2)', ' ledger: ', intervals, &
      ' intervals, largest closure residual ', worst
  if (csv) close(unit_csv)
  call vi_sim_destroy(sim)
  call vi_model_destroy(model)
  if (c_associated(sim) .or. c_associated(model)) stop 'destroy did not clear the handles'
end program fig2
