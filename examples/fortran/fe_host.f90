! fe_host.f90 - a Fortran finite-element code hands its structure to
! vibroimpact (vi_sparse.h), twice:
!
!  A. its sparse M and K as Fortran CSC arrays, 1-based, both triangles
!     stored (VI_CSC_FULL): vibroimpact finds the 10 lowest modes;
!  B. its own modes (vi_model_create_modal): frequencies, 2 % modal damping,
!     and the row of its mode shapes at the stop, which is also where the
!     load acts; the host projects the load itself (Psi^T f).
!
! The structure is examples/c/fe_host.c's: a clamped-free steel rod of 200
! linear elements (consistent mass), a stop 20 micrometres beyond the free
! end (r = 0.7), a harmonic end load at 0.9 times the first frequency.
! Both models give the same impacts; the program stops with code 1 if they
! disagree beyond 1e-7 of a period.
!
!   vi_fe_host_fortran
module fe_host_events
  use, intrinsic :: iso_c_binding
  use vibroimpact
  implicit none
  integer, parameter :: maximp = 4096
  real(c_double) :: times(maximp, 2), vns(maximp, 2)
  integer :: counts(2) = 0, which = 1
contains
  integer(c_int) function on_event(ev, user) bind(C)
    type(vi_event), intent(in) :: ev
    type(c_ptr), value :: user
    on_event = merge(1, 0, c_associated(user))  ! no user data: go on
    if (ev%kind /= VI_EVENT_IMPACT .or. counts(which) >= maximp) return
    counts(which) = counts(which) + 1
    times(counts(which), which) = ev%t
    vns(counts(which), which) = ev%vn
  end function

  subroutine run(model, t_end)
    type(c_ptr), intent(in) :: model
    real(c_double), intent(in) :: t_end
    type(c_ptr) :: sim
    integer(c_int) :: st
    st = vi_sim_create(model, sim)
    if (st == VI_OK) st = vi_sim_set_method(sim, VI_METHOD_EXACT)
    if (st == VI_OK) st = vi_sim_set_tolerances(sim, 1d-11, 1d-16)
    if (st == VI_OK) st = vi_sim_set_event_callback(sim, c_funloc(on_event), c_null_ptr, &
                                                    c_null_funptr)
    ! on_event reads t and vn only: events without states (O(n) bounces)
    if (st == VI_OK) st = vi_sim_set_event_states(sim, 0)
    if (st == VI_OK) st = vi_sim_run(sim, t_end)
    if (st < 0) then
      print *, 'run: ', vi_string(vi_sim_errmsg(sim))
      stop 1
    end if
    call vi_sim_destroy(sim)
  end subroutine
end module

program fe_host
  use, intrinsic :: iso_c_binding
  use vibroimpact
  use fe_host_events
  implicit none
  integer, parameter :: n = 200, nk = 10
  real(c_double), parameter :: young = 210d9, rho = 7800d0, area = 3.14d-4, len = 1d0
  real(c_double), parameter :: pi = 3.14159265358979324d0
  integer(c_int) :: colptr(n + 1), rowind(3 * n), st, i, j, c, el
  real(c_double) :: mval(3 * n), kval(3 * n), load(n), omega(nk), psi(nk), zeta(nk), fq(nk)
  real(c_double) :: h, ke, me, th, s, q, om, xs, r, t_end, dmax
  type(c_ptr) :: fe, ma, mb

  h = len / n
  ke = young * area / h
  me = rho * area * h / 6
  ! the host's assembly, full storage, 1-based: dof j is node j (node 0 clamped)
  c = 1
  do j = 1, n
    colptr(j) = c
    if (j > 1) then
      rowind(c) = j - 1; kval(c) = -ke; mval(c) = me; c = c + 1
    end if
    rowind(c) = j
    kval(c) = ke * merge(2, 1, j < n); mval(c) = 2 * me * merge(2, 1, j < n); c = c + 1
    if (j < n) then
      rowind(c) = j + 1; kval(c) = -ke; mval(c) = me; c = c + 1
    end if
  end do
  colptr(n + 1) = c
  ! the host's modes: mode j samples sin(i theta_j), mass-normalised
  do j = 1, nk
    th = (2 * j - 1) * pi / (2 * n)
    s = sin(th / 2)
    omega(j) = sqrt(6 * young / (rho * h * h) * 2 * s * s / (2 + cos(th)))
    q = 0
    do el = 0, n - 1
      q = q + me * (2 * sin(el * th)**2 + 2 * sin(el * th) * sin((el + 1) * th) &
                    + 2 * sin((el + 1) * th)**2)
    end do
    psi(j) = sin(n * th) / sqrt(q)
  end do
  om = 0.9d0 * omega(1)
  zeta = 0.02d0
  xs = 2d-5
  r = 0.7d0
  t_end = 20 * 2 * pi / om
  load = 0
  load(n) = 1d3

  ! A. sparse matrices (dofs are 0-based in vi_fe_add_stop_dof: n - 1)
  st = vi_fe_create(n, fe)
  if (st == VI_OK) st = vi_fe_set_mass_csc(fe, VI_CSC_FULL, 1, colptr, rowind, mval)
  if (st == VI_OK) st = vi_fe_set_stiffness_csc(fe, VI_CSC_FULL, 1, colptr, rowind, kval)
  if (st == VI_OK) st = vi_fe_set_modes(fe, nk)
  if (st == VI_OK) st = vi_fe_set_modal_damping(fe, 1, zeta)
  if (st == VI_OK) st = vi_fe_add_stop_dof(fe, n - 1, 1, xs, r)
  if (st == VI_OK) st = vi_fe_set_forcing(fe, om, a=load)
  if (st == VI_OK) st = vi_fe_setup(fe)
  if (st == VI_OK) st = vi_fe_create_model(fe, ma)
  if (st /= VI_OK) then
    print *, 'A: ', vi_string(vi_strerror(st)), ' ', vi_string(vi_fe_errmsg(fe))
    stop 1
  end if
  print '(a,f12.4,a,es9.2)', ' A. from CSC M, K: omega_1 =', omega_of(fe), &
      ' rad/s, backward error', vi_fe_residual(fe)
  call vi_fe_destroy(fe)

  ! B. a model from the host's modes: stop row Psi(n, :), load Psi^T f
  fq = 1d3 * psi
  st = vi_model_create_modal(nk, omega, zeta=zeta, ldd=0, model=mb)
  if (st == VI_OK) st = vi_model_set_stop(mb, psi, xs, r)
  if (st == VI_OK) st = vi_model_set_forcing(mb, om, a=fq)
  if (st == VI_OK) st = vi_model_setup(mb)
  if (st /= VI_OK) then
    print *, 'B: ', vi_string(vi_strerror(st))
    stop 1
  end if

  which = 1
  call run(ma, t_end)
  which = 2
  call run(mb, t_end)
  dmax = 0
  do i = 1, min(counts(1), counts(2))
    dmax = max(dmax, abs(times(i, 1) - times(i, 2)) * om / (2 * pi))
  end do
  do i = 1, min(5, counts(1), counts(2))
    print '(a,i2,a,es16.9,a,es16.9,a,es13.6,a,es13.6)', ' impact', i, ': t =', &
        times(i, 1), ' (A)', times(i, 2), ' (B) s, v_n =', vns(i, 1), ' (A)', vns(i, 2)
  end do
  print '(i0,a,i0,a,es9.2,a)', counts(1), ' and ', counts(2), &
      ' impacts in 20 forcing periods; largest time difference ', dmax, ' periods'
  call vi_model_destroy(ma)
  call vi_model_destroy(mb)
  if (counts(1) /= counts(2) .or. counts(1) == 0 .or. dmax > 1d-7) stop 1
contains
  real(c_double) function omega_of(h_fe)
    type(c_ptr), intent(in) :: h_fe
    real(c_double), pointer :: w(:)
    call c_f_pointer(vi_fe_omega(h_fe), w, [nk])
    omega_of = w(1)
  end function
end program
