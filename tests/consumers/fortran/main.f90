! Outside consumer: built with pkg-config and a plain gfortran command line
! against an installed vibroimpact; prints "ok" when the values hold.
program consumer
  use, intrinsic :: iso_c_binding
  use vibroimpact
  use vibroimpact_io, only: vi_diag, vi_chars  ! the installed .mod; no HDF5 needed
  implicit none
  type(vi_diag) :: diag
  real(c_double) :: mass(2) = 1, k(2) = 1, c(2) = 0.1_c_double, M(2, 2), Cm(2, 2), Km(2, 2)
  real(c_double) :: a(2) = [0.5_c_double, 0.0_c_double], zero(2) = 0, w(2) = [0.0_c_double, 1.0_c_double]
  real(c_double), pointer :: omega(:)
  type(c_ptr) :: model = c_null_ptr, sim = c_null_ptr
  integer(c_int) :: st
  integer(c_int64_t) :: impacts
  diag%key = c_null_char
  diag%key(1:3) = ['a', 'b', c_null_char]
  if (vi_chars(diag%key) /= 'ab') stop 1
  st = vi_build_chain(2, mass, k, c, M, Cm, Km, 2)
  st = vi_model_create(2, model)
  st = ior(st, vi_model_set_mass(model, M, 2))
  st = ior(st, vi_model_set_damping(model, Cm, 2))
  st = ior(st, vi_model_set_stiffness(model, Km, 2))
  st = ior(st, vi_model_set_forcing(model, 0.9_c_double, a, zero, zero))
  st = ior(st, vi_model_set_stop(model, w, 0.1_c_double, 0.7_c_double))
  st = ior(st, vi_model_setup(model))
  if (st /= VI_OK) stop 1
  call c_f_pointer(vi_model_omega(model), omega, [2])
  st = vi_sim_create(model, sim)
  st = ior(st, vi_sim_run(sim, 100 * 2 * acos(-1.0_c_double) / 0.9_c_double))
  impacts = vi_sim_stat(sim, VI_STAT_IMPACTS)
  if (st /= VI_OK .or. impacts /= 100 .or. abs(omega(2) - (sqrt(5.0_c_double) + 1) / 2) > 1e-14) then
    print '(a)', 'FAIL: '//vi_string(vi_sim_errmsg(sim))
    stop 1
  end if
  print '(a,f18.15,a,i0,a)', 'ok: omega_2 = ', omega(2), ', ', impacts, ' impacts'
  call vi_sim_destroy(sim)
  call vi_model_destroy(model)
end program consumer
