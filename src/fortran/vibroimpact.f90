! vibroimpact.f90 - Fortran 2003 interface to the vibroimpact C library.
!
!   use vibroimpact
!
! Every routine is the C function of the same name (include/vibroimpact/*.h
! documents units, ownership and errors).  Handles are type(c_ptr), created
! by vi_*_create and released by vi_*_destroy, which also nullify them.
! Matrices are Fortran arrays passed straight through, column-major with
! their leading dimension: no copies.  Indices that the C API counts from 0
! (mode numbers in vi_orbit_reduced_restitution, vi_model_create_reduced
! and vi_cantilever_*, vi_event%index) stay 0-based here.  Callbacks are bind(C) functions passed with c_funloc; they
! return 0 to go on and non-zero to stop the run.  Messages come back as
! Fortran strings through vi_string.  Arguments the C API lets be NULL are
! optional here (an absent one is passed as NULL: Fortran 2018, TS 29113,
! in gfortran since 4.9; the rest is Fortran 2003); strings going into C end
! with c_null_char ('exact'//c_null_char).  The scene and HDF5 functions of
! the companion library are in module vibroimpact_io (vibroimpact_io.f90).
!
! tests/fortran_symbols_test.sh fails when an exported C function has no
! bind(C) interface here or in vibroimpact_io.f90, when an interface's
! arguments or result differ from the C prototype, and when a header's
! enumerator is not among the constants (src/fortran/vi_gen_constants.c).
module vibroimpact
  use, intrinsic :: iso_c_binding
  implicit none
  private

  include 'vi_constants.inc'

  !> An event as the event callback sees it (vi_event in vi_sim.h).
  type, bind(C), public :: vi_event
    integer(c_int) :: kind, n
    integer(c_int64_t) :: index
    real(c_double) :: t, vn, ie
    type(c_ptr) :: x, v_minus, v_plus   ! real(c_double) [n]: use c_f_pointer
    integer(c_int) :: stop               ! 0-based stop index (vi_model_add_stop)
  end type

  !> Progress as the monitor sees it (vi_progress in vi_sim.h).
  type, bind(C), public :: vi_progress
    real(c_double) :: t, t_start, t_end
    integer(c_int64_t) :: steps, impacts
  end type

  !> One ledger interval as the ledger callback sees it (vi_ledger.h);
  !> the arrays are real(c_double) [n]: use c_f_pointer.
  type, bind(C), public :: vi_ledger_interval
    integer(c_int) :: n
    real(c_double) :: t_a, t_b
    type(c_ptr) :: Ea, Eb, Ka, Kb, FE, DE, XE, CE, jumps  ! jumps: C dE (may be null)
    real(c_double) :: ie, residual
    type(c_ptr) :: NE  ! work of the nonlinear forces (vi_force.h)
  end type

  public :: vi_string
  public :: vi_status_name, vi_strerror, vi_version_number, vi_version_string, &
            vi_sundials_version
  public :: vi_model_create, vi_model_destroy, vi_model_set_mass, &
            vi_model_set_damping, vi_model_set_stiffness, vi_model_set_forcing, &
            vi_model_set_stop, vi_model_add_stop, vi_model_num_stops, &
            vi_model_stop, vi_model_delassus, vi_model_setup, vi_model_errmsg, vi_model_n, &
            vi_model_omega, vi_model_zeta, vi_model_modal_shapes, &
            vi_model_modal_stop, vi_model_is_proportional, vi_model_to_modal, &
            vi_model_from_modal, vi_model_energy, vi_model_stop_compliance, &
            vi_model_check_run, &
            vi_model_omega_forcing, vi_model_forcing_period, vi_model_clearance, vi_model_restitution, &
            vi_model_mass, vi_model_damping, vi_model_stiffness, vi_model_stop_vector, &
            vi_model_forcing_cos, vi_model_forcing_sin, vi_model_forcing_const, &
            vi_model_modal_damping, vi_model_modal_forcing_cos, &
            vi_model_modal_forcing_sin, vi_model_modal_forcing_const, &
            vi_model_create_reduced, vi_model_create_truncated, &
            vi_model_modal_compliance
  public :: vi_model_create_band, vi_model_set_mass_band, vi_model_set_damping_band, &
            vi_model_set_stiffness_band, vi_model_create_chain, vi_model_memory_estimate, &
            vi_model_memory, vi_model_bandwidth, vi_model_mass_band, vi_model_omega_bound, &
            vi_model_damping_band, vi_model_stiffness_band, vi_build_chain_band
  public :: vi_sweep_create, vi_sweep_destroy, vi_sweep_errmsg, vi_sweep_set_periods, &
            vi_sweep_set_classify, vi_sweep_set_run, vi_sweep_set_initial, vi_sweep_set_warm, &
            vi_sweep_set_param, vi_sweep_param, vi_sweep_reset, vi_sweep_set_monitor, &
            vi_sweep_warm_state, vi_sweep_set_warm_state, &
            vi_sweep_set_sim_hook, vi_sweep_set_cancel, vi_sweep_set_orbits, vi_sweep_iterate, &
            vi_sweep_period, vi_sweep_failed, vi_sweep_forcing_period, vi_sweep_impacts, &
            vi_sweep_strobe, vi_sweep_orbits, vi_sweep_model, vi_sweep_attractors, &
            vi_sweep_set_lyapunov, vi_sweep_lyapunov
  public :: vi_cont_create, vi_cont_destroy, vi_cont_errmsg, vi_cont_set_range, &
            vi_cont_set_orbit, vi_cont_set_monitor, vi_cont_set_cancel, vi_cont_iterate, vi_cont_done, &
            vi_cont_point, vi_cont_orbit, vi_cont_num_events, vi_cont_event, &
            vi_cont_refine, vi_cont_refine_pnm, vi_cont_curve_create, vi_cont_curve_destroy, vi_cont_curve_errmsg, &
            vi_cont_curve_set_orbit, vi_cont_curve_set_impacts, vi_cont_curve_locate, &
            vi_cont_curve_set_range, vi_cont_curve_iterate, vi_cont_curve_done, &
            vi_cont_curve_start, vi_cont_curve_point, vi_cont_curve_impacts, &
            vi_cont_curve_num_special, vi_cont_curve_special
  public :: vi_truncation_create, vi_truncation_create_fe, vi_truncation_destroy, &
            vi_truncation_errmsg, vi_truncation_set_modes, vi_truncation_set_initial, &
            vi_truncation_set_monitor, vi_truncation_set_cancel, vi_truncation_iterate, &
            vi_truncation_done, vi_truncation_row, vi_truncation_table, &
            vi_truncation_summary, vi_truncation_model
  public :: vi_census_create, vi_census_destroy, vi_census_errmsg, vi_census_set_phases, &
            vi_census_set_initial, vi_census_set_sim_hook, vi_census_set_monitor, &
            vi_census_set_cancel, vi_census_run, vi_census_count, vi_census_orbit, &
            vi_census_stability
  public :: vi_model_set_param, vi_model_param, vi_model_copy, vi_param_kind, &
            vi_model_check_param, &
            vi_param_set_initial, vi_param_initial, vi_param_key_count, vi_param_key_name
  public :: vi_identify_create, vi_identify_destroy, vi_identify_errmsg, &
            vi_identify_set_param, vi_identify_set_param_key, vi_identify_set_builder, &
            vi_identify_set_cancel, &
            vi_identify_set_observation, vi_identify_set_shift, vi_identify_set_noise, &
            vi_identify_set_data, vi_identify_run, vi_identify_params, vi_identify_shift, &
            vi_identify_correlation, vi_identify_summary, vi_identify_nparams, &
            vi_identify_orbit_period, vi_identify_response, vi_identify_energy_restitution, &
            vi_identify_outliers, &
            vi_identify_set_stable_only, vi_identify_stability, vi_identify_forcing_phase, &
            vi_identify_set_sensors, vi_identify_set_global, vi_identify_profile, &
            vi_identify_nsolutions, vi_identify_solution, vi_identify_solution_profile, &
            vi_identify_solution_summary, vi_identify_search_range, vi_identify_add_channel, &
            vi_identify_solution_separation
  public :: vi_fe_create, vi_fe_destroy, vi_fe_errmsg, vi_fe_set_mass_csc, &
            vi_fe_set_stiffness_csc, vi_fe_set_damping_csc, vi_fe_set_rayleigh, &
            vi_fe_set_modal_damping, vi_fe_set_modes, vi_fe_set_shift, &
            vi_fe_set_eigensolver, vi_fe_set_memory_limit, vi_fe_set_host_modes, &
            vi_fe_add_stop, vi_fe_add_stop_dof, vi_fe_set_forcing, vi_fe_set_outputs, &
            vi_fe_set_keep_shapes, vi_fe_setup, vi_fe_create_model, vi_fe_n, &
            vi_fe_num_modes, vi_fe_omega, vi_fe_modal_damping, vi_fe_modal_stops, &
            vi_fe_num_stops, vi_fe_output_shapes, vi_fe_shapes, vi_fe_shift, &
            vi_fe_residual, vi_fe_stop_compliance, vi_fe_matrix_csc, vi_fe_to_outputs, &
            vi_fe_to_modal, vi_fe_memory_estimate, vi_model_create_modal, &
            vi_fe_set_rigid_modes, vi_fe_set_accuracy, vi_fe_summary, &
            vi_fe_mode_residuals, vi_fe_mode_rigidity
  public :: vi_build_chain, vi_build_cantilever, vi_cantilever_beta, &
            vi_cantilever_shape, vi_cantilever_participation
  public :: vi_impact_apply, vi_impact_apply_r, vi_impact_apply_multi, vi_restitution_from_energy, &
            vi_flow_physical, vi_flow_modal
  public :: vi_method_name, vi_method_from_name, vi_stat_name
  public :: vi_sim_create, vi_sim_destroy, vi_sim_errmsg, vi_sim_set_method, &
            vi_sim_set_tolerances, vi_sim_set_initial, vi_sim_set_event_callback, &
            vi_sim_set_sampling, vi_sim_set_monitor, vi_sim_run, vi_sim_state, &
            vi_sim_stat, vi_sim_is_sticking, vi_sim_set_native_vector_ops, &
            vi_sim_set_chatter_threshold, vi_sim_set_restart_step, vi_sim_set_max_step, &
            vi_sim_set_cancel, vi_sim_set_floors, vi_sim_method_used, vi_sim_method_note, &
            vi_sim_setup, vi_sim_run_to_event, vi_sim_n, &
            vi_sim_set_impact_resolution, vi_sim_velocity_scale, &
            vi_sim_set_event_states
  public :: vi_sim_enable_ledger, vi_sim_ledger, vi_sim_ledger_max_residual, &
            vi_sim_set_ledger_callback
  public :: vi_sim_set_force, vi_sim_add_spring, vi_sim_clear_springs, &
            vi_sim_ledger_force, vi_sim_stop_losses
  public :: vi_orbit_create, vi_orbit_destroy, vi_orbit_errmsg, vi_orbit_set_method, &
            vi_orbit_set_tolerances, vi_orbit_find, vi_orbit_classify, &
            vi_orbit_balance, vi_orbit_modal_balance, vi_orbit_reduced_restitution, &
            vi_orbit_set_initial, vi_orbit_set_transient, vi_orbit_set_monitor, &
            vi_orbit_set_cancel, vi_orbit_impact_state, vi_orbit_multipliers, vi_orbit_min_gap
  public :: vi_orbit_set_direct_search, vi_orbit_search_info, vi_orbit_pnm_solve, &
            vi_orbit_pnm_multipliers, vi_orbit_pnm_admissible, vi_orbit_p1_scan, &
            vi_orbit_p1_scan_polled, &
            vi_orbit_pnm_residual, vi_orbit_pnm_monodromy, vi_orbit_pnm_solve_stops, &
            vi_orbit_pnm_residual_stops, vi_orbit_pnm_multipliers_stops, &
            vi_orbit_pnm_admissible_stops, vi_orbit_pnm_dparam, vi_orbit_impacts, &
            vi_orbit_stop_balance, vi_orbit_stop_modal_balance, vi_orbit_lyapunov

  interface
    ! ---- status and version -------------------------------------------------
    type(c_ptr) function vi_status_name(code) bind(C, name="vi_status_name")
      import :: c_ptr, c_int
      integer(c_int), value :: code
    end function
    type(c_ptr) function vi_strerror(code) bind(C, name="vi_strerror")
      import :: c_ptr, c_int
      integer(c_int), value :: code
    end function
    integer(c_int) function vi_version_number() bind(C, name="vi_version_number")
      import :: c_int
    end function
    type(c_ptr) function vi_version_string() bind(C, name="vi_version_string")
      import :: c_ptr
    end function
    type(c_ptr) function vi_sundials_version() bind(C, name="vi_sundials_version")
      import :: c_ptr
    end function

    ! ---- model ----------------------------------------------------------------
    integer(c_int) function vi_model_create(n, model) bind(C, name="vi_model_create")
      import :: c_int, c_ptr
      integer(c_int), value :: n
      type(c_ptr) :: model
    end function
    ! band storage: AB(kd+1+i-j, j) = A(i, j) for max(1, j-kd) <= i <= j
    ! (LAPACK's symmetric band 'U' form, as dsbev and dpbtrf take it)
    integer(c_int) function vi_model_create_band(n, kd, model) bind(C, name="vi_model_create_band")
      import :: c_int, c_ptr
      integer(c_int), value :: n, kd
      type(c_ptr) :: model
    end function
    integer(c_int) function vi_model_set_mass_band(model, kd, AB, ldab) bind(C, name="vi_model_set_mass_band")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: model
      integer(c_int), value :: kd, ldab
      real(c_double), intent(in) :: AB(ldab, *)
    end function
    integer(c_int) function vi_model_set_damping_band(model, kd, AB, ldab) bind(C, name="vi_model_set_damping_band")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: model
      integer(c_int), value :: kd, ldab
      real(c_double), intent(in), optional :: AB(ldab, *)  ! absent: C = 0
    end function
    integer(c_int) function vi_model_set_stiffness_band(model, kd, AB, ldab) bind(C, name="vi_model_set_stiffness_band")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: model
      integer(c_int), value :: kd, ldab
      real(c_double), intent(in) :: AB(ldab, *)
    end function
    integer(c_int) function vi_model_create_chain(n, mass, k, c, model) bind(C, name="vi_model_create_chain")
      import :: c_int, c_ptr, c_double
      integer(c_int), value :: n
      real(c_double), intent(in) :: mass(*), k(*)
      real(c_double), intent(in), optional :: c(*)  ! absent: no damping
      type(c_ptr) :: model
    end function
    integer(c_int) function vi_model_memory_estimate(n, kd, ns, method, ledger, bytes) &
        bind(C, name="vi_model_memory_estimate")
      import :: c_int, c_int64_t
      integer(c_int), value :: n, kd, ns, method, ledger
      integer(c_int64_t) :: bytes
    end function
    real(c_double) function vi_model_omega_bound(model) bind(C, name="vi_model_omega_bound")
      import :: c_double, c_ptr
      type(c_ptr), value :: model
    end function
    integer(c_int64_t) function vi_model_memory(model) bind(C, name="vi_model_memory")
      import :: c_int64_t, c_ptr
      type(c_ptr), value :: model
    end function
    integer(c_int) function vi_model_bandwidth(model) bind(C, name="vi_model_bandwidth")
      import :: c_int, c_ptr
      type(c_ptr), value :: model
    end function
    type(c_ptr) function vi_model_mass_band(model, kd, ldab) bind(C, name="vi_model_mass_band")
      import :: c_ptr, c_int
      type(c_ptr), value :: model
      integer(c_int) :: kd, ldab
    end function
    type(c_ptr) function vi_model_damping_band(model, kd, ldab) bind(C, name="vi_model_damping_band")
      import :: c_ptr, c_int
      type(c_ptr), value :: model
      integer(c_int) :: kd, ldab
    end function
    type(c_ptr) function vi_model_stiffness_band(model, kd, ldab) bind(C, name="vi_model_stiffness_band")
      import :: c_ptr, c_int
      type(c_ptr), value :: model
      integer(c_int) :: kd, ldab
    end function
    subroutine vi_model_destroy(model) bind(C, name="vi_model_destroy")
      import :: c_ptr
      type(c_ptr) :: model
    end subroutine
    integer(c_int) function vi_model_set_mass(model, M, ldm) bind(C, name="vi_model_set_mass")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: model
      integer(c_int), value :: ldm
      real(c_double), intent(in) :: M(ldm, *)
    end function
    integer(c_int) function vi_model_set_damping(model, C, ldc) bind(C, name="vi_model_set_damping")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: model
      integer(c_int), value :: ldc
      real(c_double), intent(in), optional :: C(ldc, *)  ! absent: C = 0
    end function
    integer(c_int) function vi_model_set_stiffness(model, K, ldk) bind(C, name="vi_model_set_stiffness")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: model
      integer(c_int), value :: ldk
      real(c_double), intent(in) :: K(ldk, *)
    end function
    integer(c_int) function vi_model_set_forcing(model, omega, a, b, f0) &
        bind(C, name="vi_model_set_forcing")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: model
      real(c_double), value :: omega
      real(c_double), intent(in), optional :: a(*), b(*), f0(*)  ! absent: 0
    end function
    integer(c_int) function vi_model_set_stop(model, w, x_s, r) bind(C, name="vi_model_set_stop")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: model
      real(c_double), intent(in) :: w(*)
      real(c_double), value :: x_s, r
    end function
    integer(c_int) function vi_model_add_stop(model, w, x_s, r) bind(C, name="vi_model_add_stop")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: model
      real(c_double), intent(in) :: w(*)
      real(c_double), value :: x_s, r
    end function
    integer(c_int) function vi_model_num_stops(model) bind(C, name="vi_model_num_stops")
      import :: c_int, c_ptr
      type(c_ptr), value :: model
    end function
    !> k is 0-based
    integer(c_int) function vi_model_stop(model, k, w, x_s, r) bind(C, name="vi_model_stop")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: model
      integer(c_int), value :: k
      real(c_double), optional :: w(*), x_s, r
    end function
    type(c_ptr) function vi_model_delassus(model, ld) bind(C, name="vi_model_delassus")
      import :: c_ptr, c_int
      type(c_ptr), value :: model
      integer(c_int) :: ld
    end function
    integer(c_int) function vi_model_setup(model) bind(C, name="vi_model_setup")
      import :: c_int, c_ptr
      type(c_ptr), value :: model
    end function
    type(c_ptr) function vi_model_errmsg(model) bind(C, name="vi_model_errmsg")
      import :: c_ptr
      type(c_ptr), value :: model
    end function
    integer(c_int) function vi_model_n(model) bind(C, name="vi_model_n")
      import :: c_int, c_ptr
      type(c_ptr), value :: model
    end function
    type(c_ptr) function vi_model_omega(model) bind(C, name="vi_model_omega")
      import :: c_ptr
      type(c_ptr), value :: model
    end function
    type(c_ptr) function vi_model_zeta(model) bind(C, name="vi_model_zeta")
      import :: c_ptr
      type(c_ptr), value :: model
    end function
    type(c_ptr) function vi_model_modal_shapes(model, ld) bind(C, name="vi_model_modal_shapes")
      import :: c_ptr, c_int
      type(c_ptr), value :: model
      integer(c_int) :: ld
    end function
    type(c_ptr) function vi_model_modal_stop(model) bind(C, name="vi_model_modal_stop")
      import :: c_ptr
      type(c_ptr), value :: model
    end function
    integer(c_int) function vi_model_is_proportional(model) bind(C, name="vi_model_is_proportional")
      import :: c_int, c_ptr
      type(c_ptr), value :: model
    end function
    integer(c_int) function vi_model_to_modal(model, x, q) bind(C, name="vi_model_to_modal")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: model
      real(c_double), intent(in) :: x(*)
      real(c_double) :: q(*)
    end function
    integer(c_int) function vi_model_from_modal(model, q, x) bind(C, name="vi_model_from_modal")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: model
      real(c_double), intent(in) :: q(*)
      real(c_double) :: x(*)
    end function
    real(c_double) function vi_model_energy(model, x, v) bind(C, name="vi_model_energy")
      import :: c_ptr, c_double
      type(c_ptr), value :: model
      real(c_double), intent(in) :: x(*), v(*)
    end function
    !> key: a C string (c_f_pointer it) naming the scene key of a refused value
    integer(c_int) function vi_model_check_run(model, t0, t_end, x0, v0, rtol, atol, &
        key, value, msg, len) bind(C, name="vi_model_check_run")
      import :: c_int, c_ptr, c_double, c_char
      type(c_ptr), value :: model
      real(c_double), value :: t0, t_end, rtol, atol
      real(c_double), intent(in) :: x0(*), v0(*)
      type(c_ptr) :: key
      real(c_double) :: value
      character(kind=c_char) :: msg(*)
      integer(c_int), value :: len
    end function
    real(c_double) function vi_model_stop_compliance(model) bind(C, name="vi_model_stop_compliance")
      import :: c_ptr, c_double
      type(c_ptr), value :: model
    end function
    !> Read-only views owned by the model (c_f_pointer them: matrices are
    !> [n, n], vectors [n]); null before vi_model_setup.
    real(c_double) function vi_model_omega_forcing(model) bind(C, name="vi_model_omega_forcing")
      import :: c_ptr, c_double
      type(c_ptr), value :: model
    end function
    real(c_double) function vi_model_forcing_period(model) bind(C, name="vi_model_forcing_period")
      import :: c_ptr, c_double
      type(c_ptr), value :: model
    end function
    real(c_double) function vi_model_clearance(model) bind(C, name="vi_model_clearance")
      import :: c_ptr, c_double
      type(c_ptr), value :: model
    end function
    real(c_double) function vi_model_restitution(model) bind(C, name="vi_model_restitution")
      import :: c_ptr, c_double
      type(c_ptr), value :: model
    end function
    type(c_ptr) function vi_model_mass(model) bind(C, name="vi_model_mass")
      import :: c_ptr
      type(c_ptr), value :: model
    end function
    type(c_ptr) function vi_model_damping(model) bind(C, name="vi_model_damping")
      import :: c_ptr
      type(c_ptr), value :: model
    end function
    type(c_ptr) function vi_model_stiffness(model) bind(C, name="vi_model_stiffness")
      import :: c_ptr
      type(c_ptr), value :: model
    end function
    type(c_ptr) function vi_model_stop_vector(model) bind(C, name="vi_model_stop_vector")
      import :: c_ptr
      type(c_ptr), value :: model
    end function
    type(c_ptr) function vi_model_forcing_cos(model) bind(C, name="vi_model_forcing_cos")
      import :: c_ptr
      type(c_ptr), value :: model
    end function
    type(c_ptr) function vi_model_forcing_sin(model) bind(C, name="vi_model_forcing_sin")
      import :: c_ptr
      type(c_ptr), value :: model
    end function
    type(c_ptr) function vi_model_forcing_const(model) bind(C, name="vi_model_forcing_const")
      import :: c_ptr
      type(c_ptr), value :: model
    end function
    type(c_ptr) function vi_model_modal_forcing_cos(model) bind(C, name="vi_model_modal_forcing_cos")
      import :: c_ptr
      type(c_ptr), value :: model
    end function
    type(c_ptr) function vi_model_modal_forcing_sin(model) bind(C, name="vi_model_modal_forcing_sin")
      import :: c_ptr
      type(c_ptr), value :: model
    end function
    type(c_ptr) function vi_model_modal_forcing_const(model) bind(C, name="vi_model_modal_forcing_const")
      import :: c_ptr
      type(c_ptr), value :: model
    end function
    type(c_ptr) function vi_model_modal_damping(model, ld) bind(C, name="vi_model_modal_damping")
      import :: c_ptr, c_int
      type(c_ptr), value :: model
      integer(c_int) :: ld
    end function
    !> model in modal coordinates (n_R of them); z [2 nR] and zt [2 (k + static_vector)] optional together
    integer(c_int) function vi_model_create_truncated(model, k, static_vector, r, z, zt, &
        carried, out) bind(C, name="vi_model_create_truncated")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: model
      integer(c_int), value :: k, static_vector
      real(c_double), value :: r
      real(c_double), intent(in), optional :: z(*)
      real(c_double), intent(out), optional :: zt(*), carried
      type(c_ptr), intent(out) :: out
    end function
    !> stop 0-based; dynamic, static_part [k] cumulative (optional)
    integer(c_int) function vi_model_modal_compliance(model, stop, k, dynamic, &
        static_part) bind(C, name="vi_model_modal_compliance")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: model
      integer(c_int), value :: stop, k
      real(c_double), intent(out), optional :: dynamic(*), static_part(*)
    end function
    !> The reduced model of the modes modes(1:k) (0-based mode numbers).
    integer(c_int) function vi_model_create_reduced(full, modes, k, r, model) &
        bind(C, name="vi_model_create_reduced")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: full
      integer(c_int), intent(in) :: modes(*)
      integer(c_int), value :: k
      real(c_double), value :: r
      type(c_ptr) :: model
    end function
    integer(c_int) function vi_build_chain_band(n, mass, k, c, MB, CB, KB, ldab) &
        bind(C, name="vi_build_chain_band")
      import :: c_int, c_double
      integer(c_int), value :: n, ldab
      real(c_double), intent(in) :: mass(*), k(*)
      real(c_double), intent(in), optional :: c(*)  ! absent: no damping
      real(c_double) :: MB(ldab, *), CB(ldab, *), KB(ldab, *)
    end function
    integer(c_int) function vi_build_chain(n, mass, k, c, M, Cm, Km, ld) bind(C, name="vi_build_chain")
      import :: c_int, c_double
      integer(c_int), value :: n, ld
      real(c_double), intent(in) :: mass(*), k(*)
      real(c_double), intent(in), optional :: c(*)  ! absent: no damping
      real(c_double) :: M(ld, *), Cm(ld, *), Km(ld, *)
    end function
    integer(c_int) function vi_build_cantilever(modes, omega1, zeta, xi_stop, M, Cm, Km, ld, w, gamma) &
        bind(C, name="vi_build_cantilever")
      import :: c_int, c_double
      integer(c_int), value :: modes, ld
      real(c_double), value :: omega1, zeta, xi_stop
      real(c_double) :: M(ld, *), Cm(ld, *), Km(ld, *), w(*), gamma(*)
    end function
    !> beta_j and phi_j(xi) of the cantilever, j counted from 0 (as in C).
    real(c_double) function vi_cantilever_beta(j) bind(C, name="vi_cantilever_beta")
      import :: c_int, c_double
      integer(c_int), value :: j
    end function
    real(c_double) function vi_cantilever_shape(j, xi) bind(C, name="vi_cantilever_shape")
      import :: c_int, c_double
      integer(c_int), value :: j
      real(c_double), value :: xi
    end function
    real(c_double) function vi_cantilever_participation(j) bind(C, name="vi_cantilever_participation")
      import :: c_int, c_double
      integer(c_int), value :: j
    end function

    ! ---- impact law and exact flow --------------------------------------------
    integer(c_int) function vi_impact_apply(model, v_minus, v_plus, vn, ie) bind(C, name="vi_impact_apply")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: model
      real(c_double), intent(in) :: v_minus(*)
      real(c_double) :: v_plus(*)
      real(c_double), optional :: vn, ie
    end function
    !> stops(nc) are 0-based stop indices
    integer(c_int) function vi_impact_apply_multi(model, nc, stops, v_minus, v_plus, P, ie) &
        bind(C, name="vi_impact_apply_multi")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: model
      integer(c_int), value :: nc
      integer(c_int), intent(in) :: stops(*)
      real(c_double), intent(in) :: v_minus(*)
      real(c_double) :: v_plus(*)
      real(c_double), optional :: P(*), ie(*)
    end function
    integer(c_int) function vi_impact_apply_r(model, r, v_minus, v_plus, vn, ie) &
        bind(C, name="vi_impact_apply_r")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: model
      real(c_double), value :: r
      real(c_double), intent(in) :: v_minus(*)
      real(c_double) :: v_plus(*)
      real(c_double), optional :: vn, ie
    end function
    integer(c_int) function vi_restitution_from_energy(re, ke_i, r) bind(C, name="vi_restitution_from_energy")
      import :: c_int, c_double
      real(c_double), value :: re, ke_i
      real(c_double) :: r
    end function
    integer(c_int) function vi_flow_physical(model, t0, x0, v0, t, x, v) bind(C, name="vi_flow_physical")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: model
      real(c_double), value :: t0, t
      real(c_double), intent(in) :: x0(*), v0(*)
      real(c_double) :: x(*), v(*)
    end function
    integer(c_int) function vi_flow_modal(model, t0, q0, qd0, t, q, qd) bind(C, name="vi_flow_modal")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: model
      real(c_double), value :: t0, t
      real(c_double), intent(in) :: q0(*), qd0(*)
      real(c_double) :: q(*), qd(*)
    end function

    ! ---- simulation -----------------------------------------------------------
    !> Names of methods and statistics: C strings (vi_string), null if unknown.
    type(c_ptr) function vi_method_name(method) bind(C, name="vi_method_name")
      import :: c_ptr, c_int
      integer(c_int), value :: method
    end function
    !> name: a C string, e.g. 'exact'//c_null_char; -1 if unknown.
    integer(c_int) function vi_method_from_name(name) bind(C, name="vi_method_from_name")
      import :: c_int, c_char
      character(kind=c_char), intent(in) :: name(*)
    end function
    type(c_ptr) function vi_stat_name(which) bind(C, name="vi_stat_name")
      import :: c_ptr, c_int
      integer(c_int), value :: which
    end function
    integer(c_int) function vi_sim_create(model, sim) bind(C, name="vi_sim_create")
      import :: c_int, c_ptr
      type(c_ptr), value :: model
      type(c_ptr) :: sim
    end function
    subroutine vi_sim_destroy(sim) bind(C, name="vi_sim_destroy")
      import :: c_ptr
      type(c_ptr) :: sim
    end subroutine
    type(c_ptr) function vi_sim_errmsg(sim) bind(C, name="vi_sim_errmsg")
      import :: c_ptr
      type(c_ptr), value :: sim
    end function
    integer(c_int) function vi_sim_set_method(sim, method) bind(C, name="vi_sim_set_method")
      import :: c_int, c_ptr
      type(c_ptr), value :: sim
      integer(c_int), value :: method
    end function
    integer(c_int) function vi_sim_set_tolerances(sim, rtol, atol) bind(C, name="vi_sim_set_tolerances")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: sim
      real(c_double), value :: rtol, atol
    end function
    integer(c_int) function vi_sim_set_initial(sim, t0, x0, v0) bind(C, name="vi_sim_set_initial")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: sim
      real(c_double), value :: t0
      real(c_double), intent(in), optional :: x0(*), v0(*)  ! absent: 0
    end function
    !> fn: integer(c_int) function f(ev, user) bind(C); type(vi_event), intent(in) :: ev
    !> destroy (every callback setter): subroutine d(user) bind(C) with user by
    !> value, called when the user data is replaced or the sim destroyed; or
    !> c_null_funptr to keep ownership
    integer(c_int) function vi_sim_set_event_callback(sim, fn, user, destroy) bind(C, name="vi_sim_set_event_callback")
      import :: c_int, c_ptr, c_funptr
      type(c_ptr), value :: sim, user
      type(c_funptr), value :: fn, destroy
    end function
    !> on = 1 (default): events carry x, v_minus, v_plus; 0: null pointers
    !> (the exact method then keeps a bounce in modal coordinates)
    integer(c_int) function vi_sim_set_event_states(sim, on) bind(C, name="vi_sim_set_event_states")
      import :: c_int, c_ptr
      type(c_ptr), value :: sim
      integer(c_int), value :: on
    end function
    !> fn: integer(c_int) function f(t, n, x, v, user) bind(C) with t, n by value
    integer(c_int) function vi_sim_set_sampling(sim, dt, fn, user, destroy) bind(C, name="vi_sim_set_sampling")
      import :: c_int, c_ptr, c_funptr, c_double
      type(c_ptr), value :: sim, user
      real(c_double), value :: dt
      type(c_funptr), value :: fn, destroy
    end function
    integer(c_int) function vi_sim_set_monitor(sim, every, fn, user, destroy) bind(C, name="vi_sim_set_monitor")
      import :: c_int, c_ptr, c_funptr, c_double
      type(c_ptr), value :: sim, user
      real(c_double), value :: every
      type(c_funptr), value :: fn, destroy
    end function
    !> fn: integer(c_int) function f(user) bind(C) with user by value; non-zero cancels
    integer(c_int) function vi_sim_set_cancel(sim, fn, user, destroy) bind(C, name="vi_sim_set_cancel")
      import :: c_int, c_ptr, c_funptr
      type(c_ptr), value :: sim, user
      type(c_funptr), value :: fn, destroy
    end function
    integer(c_int) function vi_sim_n(sim) bind(C, name="vi_sim_n")
      import :: c_int, c_ptr
      type(c_ptr), value :: sim
    end function
    integer(c_int) function vi_sim_set_floors(sim, vn_min, dt_min) bind(C, name="vi_sim_set_floors")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: sim
      real(c_double), value :: vn_min, dt_min
    end function
    integer(c_int) function vi_sim_set_impact_resolution(sim, ratio) &
        bind(C, name="vi_sim_set_impact_resolution")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: sim
      real(c_double), value :: ratio
    end function
    real(c_double) function vi_sim_velocity_scale(sim) bind(C, name="vi_sim_velocity_scale")
      import :: c_ptr, c_double
      type(c_ptr), value :: sim
    end function
    integer(c_int) function vi_sim_set_chatter_threshold(sim, vmin) bind(C, name="vi_sim_set_chatter_threshold")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: sim
      real(c_double), value :: vmin
    end function
    integer(c_int) function vi_sim_set_restart_step(sim, h) bind(C, name="vi_sim_set_restart_step")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: sim
      real(c_double), value :: h
    end function
    integer(c_int) function vi_sim_set_max_step(sim, hmax) bind(C, name="vi_sim_set_max_step")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: sim
      real(c_double), value :: hmax
    end function
    integer(c_int) function vi_sim_method_used(sim) bind(C, name="vi_sim_method_used")
      import :: c_int, c_ptr
      type(c_ptr), value :: sim
    end function
    type(c_ptr) function vi_sim_method_note(sim) bind(C, name="vi_sim_method_note")
      import :: c_ptr
      type(c_ptr), value :: sim
    end function
    integer(c_int) function vi_sim_set_native_vector_ops(sim, on) bind(C, name="vi_sim_set_native_vector_ops")
      import :: c_int, c_ptr
      type(c_ptr), value :: sim
      integer(c_int), value :: on
    end function
    integer(c_int) function vi_sim_run(sim, t_end) bind(C, name="vi_sim_run")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: sim
      real(c_double), value :: t_end
    end function
    integer(c_int) function vi_sim_setup(sim) bind(C, name="vi_sim_setup")
      import :: c_int, c_ptr
      type(c_ptr), value :: sim
    end function
    !> kind: the VI_EVENT_* that ended the step, -1 at t_end
    integer(c_int) function vi_sim_run_to_event(sim, t_end, kind) bind(C, name="vi_sim_run_to_event")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: sim
      real(c_double), value :: t_end
      integer(c_int) :: kind
    end function
    integer(c_int) function vi_sim_state(sim, t, x, v) bind(C, name="vi_sim_state")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: sim
      real(c_double), optional :: t, x(*), v(*)
    end function
    integer(c_int64_t) function vi_sim_stat(sim, which) bind(C, name="vi_sim_stat")
      import :: c_int64_t, c_ptr, c_int
      type(c_ptr), value :: sim
      integer(c_int), value :: which
    end function
    integer(c_int) function vi_sim_is_sticking(sim) bind(C, name="vi_sim_is_sticking")
      import :: c_int, c_ptr
      type(c_ptr), value :: sim
    end function

    ! ---- ledger ---------------------------------------------------------------
    integer(c_int) function vi_sim_enable_ledger(sim, on) bind(C, name="vi_sim_enable_ledger")
      import :: c_int, c_ptr
      type(c_ptr), value :: sim
      integer(c_int), value :: on
    end function
    integer(c_int) function vi_sim_ledger(sim, E, FE, DE, XE, CE, jumps, ie) bind(C, name="vi_sim_ledger")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: sim
      real(c_double), optional :: E(*), FE(*), DE(*), XE(*), CE(*), jumps(*), ie  ! jumps: C dE
    end function
    !> fn: integer(c_int) function f(iv, user) bind(C); type(vi_ledger_interval), intent(in) :: iv
    integer(c_int) function vi_sim_set_ledger_callback(sim, fn, user, destroy) bind(C, name="vi_sim_set_ledger_callback")
      import :: c_int, c_ptr, c_funptr
      type(c_ptr), value :: sim, user
      type(c_funptr), value :: fn, destroy
    end function
    ! ---- nonlinear forces (vi_force.h) ---------------------------------------
    !> fn: integer(c_int) function g(t, n, x, v, f, user) bind(C) with t, n, user
    !> by value and x(n), v(n), f(n) real(c_double) arrays; jac: integer(c_int)
    !> function j(t, n, x, v, dgdx, dgdv, ld, user) bind(C), or c_null_funptr
    integer(c_int) function vi_sim_set_force(sim, fn, jac, user, destroy) bind(C, name="vi_sim_set_force")
      import :: c_int, c_ptr, c_funptr
      type(c_ptr), value :: sim, user
      type(c_funptr), value :: fn, jac, destroy
    end function
    integer(c_int) function vi_sim_add_spring(sim, type, i, j, k, gap) bind(C, name="vi_sim_add_spring")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: sim
      integer(c_int), value :: type, i, j
      real(c_double), value :: k, gap
    end function
    integer(c_int) function vi_sim_clear_springs(sim) bind(C, name="vi_sim_clear_springs")
      import :: c_int, c_ptr
      type(c_ptr), value :: sim
    end function
    integer(c_int) function vi_sim_ledger_force(sim, NE) bind(C, name="vi_sim_ledger_force")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: sim
      real(c_double) :: NE(*)
    end function
    integer(c_int) function vi_sim_stop_losses(sim, ie) bind(C, name="vi_sim_stop_losses")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: sim
      real(c_double) :: ie(*)
    end function
    real(c_double) function vi_sim_ledger_max_residual(sim) bind(C, name="vi_sim_ledger_max_residual")
      import :: c_double, c_ptr
      type(c_ptr), value :: sim
    end function

    ! ---- periodic orbits --------------------------------------------------------
    integer(c_int) function vi_orbit_create(model, orbit) bind(C, name="vi_orbit_create")
      import :: c_int, c_ptr
      type(c_ptr), value :: model
      type(c_ptr) :: orbit
    end function
    subroutine vi_orbit_destroy(orbit) bind(C, name="vi_orbit_destroy")
      import :: c_ptr
      type(c_ptr) :: orbit
    end subroutine
    type(c_ptr) function vi_orbit_errmsg(orbit) bind(C, name="vi_orbit_errmsg")
      import :: c_ptr
      type(c_ptr), value :: orbit
    end function
    integer(c_int) function vi_orbit_set_method(orbit, method) bind(C, name="vi_orbit_set_method")
      import :: c_int, c_ptr
      type(c_ptr), value :: orbit
      integer(c_int), value :: method
    end function
    integer(c_int) function vi_orbit_set_tolerances(orbit, rtol, atol) bind(C, name="vi_orbit_set_tolerances")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: orbit
      real(c_double), value :: rtol, atol
    end function
    integer(c_int) function vi_orbit_set_initial(orbit, x0, v0) bind(C, name="vi_orbit_set_initial")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: orbit
      real(c_double), intent(in), optional :: x0(*), v0(*)  ! absent: 0
    end function
    integer(c_int) function vi_orbit_set_transient(orbit, max_periods, tol) &
        bind(C, name="vi_orbit_set_transient")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: orbit
      real(c_double), value :: max_periods, tol
    end function
    !> fn as for vi_sim_set_monitor
    integer(c_int) function vi_orbit_set_monitor(orbit, fn, user, destroy) bind(C, name="vi_orbit_set_monitor")
      import :: c_int, c_ptr, c_funptr
      type(c_ptr), value :: orbit, user
      type(c_funptr), value :: fn, destroy
    end function
    !> fn: integer(c_int) function f(user) bind(C), user by value
    integer(c_int) function vi_orbit_set_cancel(orbit, fn, user, destroy) &
        bind(C, name="vi_orbit_set_cancel")
      import :: c_int, c_ptr, c_funptr
      type(c_ptr), value :: orbit, user
      type(c_funptr), value :: fn, destroy
    end function
    integer(c_int) function vi_orbit_find(orbit) bind(C, name="vi_orbit_find")
      import :: c_int, c_ptr
      type(c_ptr), value :: orbit
    end function
    integer(c_int) function vi_orbit_classify(orbit, n, m) bind(C, name="vi_orbit_classify")
      import :: c_int, c_ptr
      type(c_ptr), value :: orbit
      integer(c_int) :: n, m
    end function
    integer(c_int) function vi_orbit_balance(orbit, period, phase, vN, KE_i, RE, IE, r_rec, closure) &
        bind(C, name="vi_orbit_balance")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: orbit
      real(c_double), optional :: period, phase, vN, KE_i, RE, IE, r_rec, closure
    end function
    integer(c_int) function vi_orbit_modal_balance(orbit, FE, DE, XE, r_eff) bind(C, name="vi_orbit_modal_balance")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: orbit
      real(c_double), optional :: FE(*), DE(*), XE(*), r_eff(*)
    end function
    integer(c_int) function vi_orbit_impact_state(orbit, t, x, v) bind(C, name="vi_orbit_impact_state")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: orbit
      real(c_double), optional :: t, x(*), v(*)
    end function
    !> re, im: [2n]
    integer(c_int) function vi_orbit_multipliers(orbit, re, im) bind(C, name="vi_orbit_multipliers")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: orbit
      real(c_double) :: re(*), im(*)
    end function
    integer(c_int) function vi_orbit_lyapunov(orbit, transient, periods, lambda, spread) &
        bind(C, name="vi_orbit_lyapunov")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: orbit
      real(c_double), value :: transient, periods
      real(c_double) :: lambda
      real(c_double), optional :: spread  ! absent: not wanted
    end function
    integer(c_int) function vi_orbit_min_gap(orbit, gmin) bind(C, name="vi_orbit_min_gap")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: orbit
      real(c_double) :: gmin
    end function
    integer(c_int) function vi_orbit_reduced_restitution(orbit, modes, k, r_S) &
        bind(C, name="vi_orbit_reduced_restitution")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: orbit
      integer(c_int), intent(in) :: modes(*)
      integer(c_int), value :: k
      real(c_double) :: r_S
    end function
    !> the analysed orbit's impacts: t, stop, vn [count]; x, v [ld x count]
    integer(c_int) function vi_orbit_impacts(orbit, count, t, stop, vn, x, v, ld) &
        bind(C, name="vi_orbit_impacts")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: orbit
      integer(c_int), optional :: count
      real(c_double), optional :: t(*), vn(*), x(*), v(*)
      integer(c_int), optional :: stop(*)
      integer(c_int), value :: ld
    end function
    !> WB 11-13 for stop k (0-based)
    integer(c_int) function vi_orbit_stop_balance(orbit, k, count, KE_i, RE, IE, r_rec, &
        closure) bind(C, name="vi_orbit_stop_balance")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: orbit
      integer(c_int), value :: k
      integer(c_int), optional :: count
      real(c_double), optional :: KE_i, RE, IE, r_rec, closure
    end function
    !> FE, DE, XE [n] of stop k's approaches
    integer(c_int) function vi_orbit_stop_modal_balance(orbit, k, FE, DE, XE) &
        bind(C, name="vi_orbit_stop_modal_balance")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: orbit
      integer(c_int), value :: k
      real(c_double), optional :: FE(*), DE(*), XE(*)
    end function
    ! ---- P(n, m) orbits found directly (vi_orbit_pnm.c) --------------------
    integer(c_int) function vi_orbit_set_direct_search(orbit, on) &
        bind(C, name="vi_orbit_set_direct_search")
      import :: c_int, c_ptr
      type(c_ptr), value :: orbit
      integer(c_int), value :: on
    end function
    integer(c_int) function vi_orbit_search_info(orbit, tn, tm, by_scan) &
        bind(C, name="vi_orbit_search_info")
      import :: c_int, c_ptr
      type(c_ptr), value :: orbit
      integer(c_int), optional :: tn, tm, by_scan
    end function
    !> t [mi]; x, v [ld x mi]: the seed in, the orbit out
    integer(c_int) function vi_orbit_pnm_solve(model, n, mi, t, x, v, ld, tol, iters) &
        bind(C, name="vi_orbit_pnm_solve")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: model
      integer(c_int), value :: n, mi, ld
      real(c_double) :: t(*), x(*), v(*)
      real(c_double), value :: tol
      integer(c_int), optional :: iters
    end function
    !> F [D], J [D x D] (optional), D = mi (2 n_coords + 1)
    integer(c_int) function vi_orbit_pnm_residual(model, n, mi, t, x, v, ld, F, J) &
        bind(C, name="vi_orbit_pnm_residual")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: model
      integer(c_int), value :: n, mi, ld
      real(c_double), intent(in) :: t(*), x(*), v(*)
      real(c_double) :: F(*)
      real(c_double), optional :: J(*)
    end function
    !> re, im: [2 n_coords]
    integer(c_int) function vi_orbit_pnm_multipliers(model, n, mi, t, x, v, ld, re, im) &
        bind(C, name="vi_orbit_pnm_multipliers")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: model
      integer(c_int), value :: n, mi, ld
      real(c_double), intent(in) :: t(*), x(*), v(*)
      real(c_double) :: re(*), im(*)
    end function
    integer(c_int) function vi_orbit_pnm_admissible(model, n, mi, t, x, v, ld, gmax, ok) &
        bind(C, name="vi_orbit_pnm_admissible")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: model
      integer(c_int), value :: n, mi, ld
      real(c_double), intent(in) :: t(*), x(*), v(*)
      real(c_double), optional :: gmax
      integer(c_int) :: ok
    end function
    !> Mo [2 n_coords x 2 n_coords]; stop [mi] 0-based or omitted (all on stop 0)
    integer(c_int) function vi_orbit_pnm_monodromy(model, n, mi, stop, t, x, v, ld, Mo) &
        bind(C, name="vi_orbit_pnm_monodromy")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: model
      integer(c_int), value :: n, mi, ld
      integer(c_int), intent(in), optional :: stop(*)
      real(c_double), intent(in) :: t(*), x(*), v(*)
      real(c_double) :: Mo(*)
    end function
    !> the P(n, m) functions with the stop (0-based) of each impact, stop [mi]
    integer(c_int) function vi_orbit_pnm_solve_stops(model, n, mi, stop, t, x, v, ld, tol, &
        iters) bind(C, name="vi_orbit_pnm_solve_stops")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: model
      integer(c_int), value :: n, mi, ld
      integer(c_int), intent(in), optional :: stop(*)
      real(c_double) :: t(*), x(*), v(*)
      real(c_double), value :: tol
      integer(c_int), optional :: iters
    end function
    integer(c_int) function vi_orbit_pnm_residual_stops(model, n, mi, stop, t, x, v, ld, F, &
        J) bind(C, name="vi_orbit_pnm_residual_stops")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: model
      integer(c_int), value :: n, mi, ld
      integer(c_int), intent(in), optional :: stop(*)
      real(c_double), intent(in) :: t(*), x(*), v(*)
      real(c_double) :: F(*)
      real(c_double), optional :: J(*)
    end function
    integer(c_int) function vi_orbit_pnm_multipliers_stops(model, n, mi, stop, t, x, v, ld, &
        re, im) bind(C, name="vi_orbit_pnm_multipliers_stops")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: model
      integer(c_int), value :: n, mi, ld
      integer(c_int), intent(in), optional :: stop(*)
      real(c_double), intent(in) :: t(*), x(*), v(*)
      real(c_double) :: re(*), im(*)
    end function
    integer(c_int) function vi_orbit_pnm_admissible_stops(model, n, mi, stop, t, x, v, ld, &
        gmax, ok) bind(C, name="vi_orbit_pnm_admissible_stops")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: model
      integer(c_int), value :: n, mi, ld
      integer(c_int), intent(in), optional :: stop(*)
      real(c_double), intent(in) :: t(*), x(*), v(*)
      real(c_double), optional :: gmax
      integer(c_int) :: ok
    end function
    !> dF [mi (2 n_coords + 1)]; param VI_ORBIT_PARAM_*, k the stop (0-based)
    integer(c_int) function vi_orbit_pnm_dparam(model, n, mi, stop, t, x, v, ld, param, k, &
        dF) bind(C, name="vi_orbit_pnm_dparam")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: model
      integer(c_int), value :: n, mi, ld, param, k
      integer(c_int), intent(in), optional :: stop(*)
      real(c_double), intent(in) :: t(*), x(*), v(*)
      real(c_double) :: dF(*)
    end function
    !> t [cap]; x, v [ld x cap]; found may exceed cap
    integer(c_int) function vi_orbit_p1_scan(model, n, nphase, t, x, v, ld, cap, found) &
        bind(C, name="vi_orbit_p1_scan")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: model
      integer(c_int), value :: n, nphase, ld, cap
      real(c_double) :: t(*), x(*), v(*)
      integer(c_int) :: found
    end function
    !> as vi_orbit_p1_scan; cancel: integer(c_int) function f(user) bind(C),
    !> user by value (c_null_funptr: never cancelled)
    integer(c_int) function vi_orbit_p1_scan_polled(model, n, nphase, t, x, v, ld, cap, &
        found, cancel, user) bind(C, name="vi_orbit_p1_scan_polled")
      import :: c_int, c_ptr, c_double, c_funptr
      type(c_ptr), value :: model
      integer(c_int), value :: n, nphase, ld, cap
      real(c_double) :: t(*), x(*), v(*)
      integer(c_int) :: found
      type(c_funptr), value :: cancel
      type(c_ptr), value :: user
    end function
    ! ---- parameters by key (vi_param.h); keys are C strings,
    ! e.g. 'forcing.omega'//c_null_char, with 1-based indices 'forcing.a[1]'
    ! ---- identification (vi_identify.h) ----------------------------------------
    integer(c_int) function vi_identify_create(model, np, id) bind(C, name="vi_identify_create")
      import :: c_int, c_ptr
      type(c_ptr), value :: model
      integer(c_int), value :: np
      type(c_ptr) :: id
    end function
    subroutine vi_identify_destroy(id) bind(C, name="vi_identify_destroy")
      import :: c_ptr
      type(c_ptr) :: id
    end subroutine
    type(c_ptr) function vi_identify_errmsg(id) bind(C, name="vi_identify_errmsg")
      import :: c_ptr
      type(c_ptr), value :: id
    end function
    !> j, k 0-based as in C
    integer(c_int) function vi_identify_set_param(id, j, kind, k, p0, lo, hi) &
        bind(C, name="vi_identify_set_param")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: id
      integer(c_int), value :: j, kind, k
      real(c_double), value :: p0, lo, hi
    end function
    !> key NUL-terminated (vi_chars or // c_null_char)
    integer(c_int) function vi_identify_set_param_key(id, j, key, lo, hi) &
        bind(C, name="vi_identify_set_param_key")
      import :: c_int, c_ptr, c_char, c_double
      type(c_ptr), value :: id
      integer(c_int), value :: j
      character(kind=c_char), intent(in) :: key(*)
      real(c_double), value :: lo, hi
    end function
    integer(c_int) function vi_identify_set_builder(id, fn, user, destroy) &
        bind(C, name="vi_identify_set_builder")
      import :: c_int, c_ptr, c_funptr
      type(c_ptr), value :: id, user
      type(c_funptr), value :: fn, destroy
    end function
    !> fn: integer(c_int) function f(user) bind(C), user by value
    integer(c_int) function vi_identify_set_cancel(id, fn, user, destroy) &
        bind(C, name="vi_identify_set_cancel")
      import :: c_int, c_ptr, c_funptr
      type(c_ptr), value :: id, user
      type(c_funptr), value :: fn, destroy
    end function
    !> c [n], or c_null_ptr through an optional absent argument: stop 0's w
    integer(c_int) function vi_identify_set_observation(id, c) &
        bind(C, name="vi_identify_set_observation")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: id
      real(c_double), intent(in), optional :: c(*)
    end function
    integer(c_int) function vi_identify_set_shift(id, fit, t0) bind(C, name="vi_identify_set_shift")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: id
      integer(c_int), value :: fit
      real(c_double), value :: t0
    end function
    integer(c_int) function vi_identify_set_noise(id, sigma) bind(C, name="vi_identify_set_noise")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: id
      real(c_double), value :: sigma
    end function
    !> t, x [ns]; v [ns] optional
    integer(c_int) function vi_identify_set_data(id, ns, t, x, v) bind(C, name="vi_identify_set_data")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: id
      integer(c_int), value :: ns
      real(c_double), intent(in) :: t(*), x(*)
      real(c_double), intent(in), optional :: v(*)
    end function
    !> t [ns]; x, v, a [ns] each optional (at least one)
    integer(c_int) function vi_identify_set_sensors(id, ns, t, x, v, a) &
        bind(C, name="vi_identify_set_sensors")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: id
      integer(c_int), value :: ns
      real(c_double), intent(in) :: t(*)
      real(c_double), intent(in), optional :: x(*), v(*), a(*)
    end function
    !> c [n], y [ns]
    integer(c_int) function vi_identify_add_channel(id, c, order, y) &
        bind(C, name="vi_identify_add_channel")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: id
      real(c_double), intent(in) :: c(*), y(*)
      integer(c_int), value :: order
    end function
    integer(c_int) function vi_identify_set_global(id, on) bind(C, name="vi_identify_set_global")
      import :: c_int, c_ptr
      type(c_ptr), value :: id
      integer(c_int), value :: on
    end function
    !> arrays [np], each optional
    integer(c_int) function vi_identify_profile(id, plo95, phi95, flags) &
        bind(C, name="vi_identify_profile")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: id
      real(c_double), optional :: plo95(*), phi95(*)
      integer(c_int), optional :: flags(*)
    end function
    integer(c_int) function vi_identify_nsolutions(id, unique) bind(C, name="vi_identify_nsolutions")
      import :: c_int, c_ptr
      type(c_ptr), value :: id
      integer(c_int), optional :: unique
    end function
    !> k 0-based; arrays [np], each optional
    integer(c_int) function vi_identify_solution(id, k, p, se, lo95, hi95, flags) &
        bind(C, name="vi_identify_solution")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: id
      integer(c_int), value :: k
      real(c_double), optional :: p(*), se(*), lo95(*), hi95(*)
      integer(c_int), optional :: flags(*)
    end function
    integer(c_int) function vi_identify_solution_profile(id, k, plo95, phi95, flags) &
        bind(C, name="vi_identify_solution_profile")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: id
      integer(c_int), value :: k
      real(c_double), optional :: plo95(*), phi95(*)
      integer(c_int), optional :: flags(*)
    end function
    integer(c_int) function vi_identify_solution_summary(id, k, n, m, rms, ratio, dchi2, t0) &
        bind(C, name="vi_identify_solution_summary")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: id
      integer(c_int), value :: k
      integer(c_int), optional :: n, m
      real(c_double), optional :: rms, ratio, dchi2, t0
    end function
    integer(c_int) function vi_identify_solution_separation(id, k, d, length) &
        bind(C, name="vi_identify_solution_separation")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: id
      integer(c_int), value :: k
      real(c_double), optional :: d, length
    end function
    !> lo, hi [np], each optional
    integer(c_int) function vi_identify_search_range(id, lo, hi) &
        bind(C, name="vi_identify_search_range")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: id
      real(c_double), optional :: lo(*), hi(*)
    end function
    integer(c_int) function vi_identify_run(id) bind(C, name="vi_identify_run")
      import :: c_int, c_ptr
      type(c_ptr), value :: id
    end function
    !> arrays [np], each optional
    integer(c_int) function vi_identify_params(id, p, se, lo95, hi95, flags) &
        bind(C, name="vi_identify_params")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: id
      real(c_double), optional :: p(*), se(*), lo95(*), hi95(*)
      integer(c_int), optional :: flags(*)
    end function
    integer(c_int) function vi_identify_shift(id, t0, se) bind(C, name="vi_identify_shift")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: id
      real(c_double), optional :: t0, se
    end function
    !> R [ld x np]
    integer(c_int) function vi_identify_correlation(id, r, ld) bind(C, name="vi_identify_correlation")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: id
      real(c_double) :: r(*)
      integer(c_int), value :: ld
    end function
    integer(c_int) function vi_identify_summary(id, converged, iterations, rms, noise, &
        rcond, n, m) bind(C, name="vi_identify_summary")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: id
      integer(c_int), optional :: converged, iterations, n, m
      real(c_double), optional :: rms, noise, rcond
    end function
    integer(c_int) function vi_identify_set_stable_only(id, on) &
        bind(C, name="vi_identify_set_stable_only")
      import :: c_int, c_ptr
      type(c_ptr), value :: id
      integer(c_int), value :: on
    end function
    integer(c_int) function vi_identify_stability(id, mu) bind(C, name="vi_identify_stability")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: id
      real(c_double) :: mu
    end function
    integer(c_int) function vi_identify_nparams(id) bind(C, name="vi_identify_nparams")
      import :: c_int, c_ptr
      type(c_ptr), value :: id
    end function
    !> t [m]
    integer(c_int) function vi_identify_orbit_period(id, period, t) &
        bind(C, name="vi_identify_orbit_period")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: id
      real(c_double), optional :: period, t(*)
    end function
    !> t, x [nt]; v [nt] optional
    integer(c_int) function vi_identify_response(id, nt, t, x, v) bind(C, name="vi_identify_response")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: id
      integer(c_int), value :: nt
      real(c_double), intent(in) :: t(*)
      real(c_double) :: x(*)
      real(c_double), optional :: v(*)
    end function
    !> idx, z [cap] (idx: 0-based sample numbers); count, rest optional
    integer(c_int) function vi_identify_outliers(id, level, cap, idx, z, count, rest) &
        bind(C, name="vi_identify_outliers")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: id
      real(c_double), value :: level
      integer(c_int), value :: cap
      integer(c_int), optional :: idx(*)
      real(c_double), optional :: z(*)
      integer(c_int), optional :: count
      real(c_double), optional :: rest
    end function
    integer(c_int) function vi_identify_forcing_phase(ns, t, f, omega, t0) &
        bind(C, name="vi_identify_forcing_phase")
      import :: c_int, c_double
      integer(c_int), value :: ns
      real(c_double), intent(in) :: t(*), f(*)
      real(c_double), value :: omega
      real(c_double), intent(out) :: t0
    end function
    integer(c_int) function vi_identify_energy_restitution(id, r12, vn, ke, re) &
        bind(C, name="vi_identify_energy_restitution")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: id
      real(c_double), optional :: r12, vn, ke, re
    end function
    ! ---- parameters by key (vi_param.h); keys are C strings,
    ! e.g. 'forcing.omega'//c_null_char, with 1-based indices 'forcing.a[1]'
    integer(c_int) function vi_model_set_param(model, key, val) &
        bind(C, name="vi_model_set_param")
      import :: c_int, c_ptr, c_char, c_double
      type(c_ptr), value :: model
      character(kind=c_char), intent(in) :: key(*)
      real(c_double), value :: val
    end function
    !> what vi_model_set_param would return, m unchanged
    integer(c_int) function vi_model_check_param(model, key, val) bind(C, name="vi_model_check_param")
      import :: c_int, c_ptr, c_char, c_double
      type(c_ptr), value :: model
      character(kind=c_char), intent(in) :: key(*)
      real(c_double), value :: val
    end function
    integer(c_int) function vi_model_param(model, key, val) bind(C, name="vi_model_param")
      import :: c_int, c_ptr, c_char, c_double
      type(c_ptr), value :: model
      character(kind=c_char), intent(in) :: key(*)
      real(c_double), intent(out) :: val
    end function
    integer(c_int) function vi_model_copy(model, out) bind(C, name="vi_model_copy")
      import :: c_int, c_ptr
      type(c_ptr), value :: model
      type(c_ptr), intent(out) :: out
    end function
    integer(c_int) function vi_param_kind(key) bind(C, name="vi_param_kind")
      import :: c_int, c_char
      character(kind=c_char), intent(in) :: key(*)
    end function
    integer(c_int) function vi_param_set_initial(key, val, n, t0, x, v) &
        bind(C, name="vi_param_set_initial")
      import :: c_int, c_char, c_double
      character(kind=c_char), intent(in) :: key(*)
      real(c_double), value :: val
      integer(c_int), value :: n
      real(c_double), intent(inout) :: t0, x(*), v(*)
    end function
    integer(c_int) function vi_param_initial(key, n, t0, x, v, val) &
        bind(C, name="vi_param_initial")
      import :: c_int, c_char, c_double
      character(kind=c_char), intent(in) :: key(*)
      integer(c_int), value :: n
      real(c_double), value :: t0
      real(c_double), intent(in) :: x(*), v(*)
      real(c_double), intent(out) :: val
    end function
    integer(c_int) function vi_param_key_count() bind(C, name="vi_param_key_count")
      import :: c_int
    end function
    !> a C string (vi_string converts it); null out of range
    type(c_ptr) function vi_param_key_name(i) bind(C, name="vi_param_key_name")
      import :: c_ptr, c_int
      integer(c_int), value :: i
    end function
    ! ---- parameter studies (vi_study.h)
    integer(c_int) function vi_sweep_create(model, out) bind(C, name="vi_sweep_create")
      import :: c_int, c_ptr
      type(c_ptr), value :: model
      type(c_ptr), intent(out) :: out
    end function
    subroutine vi_sweep_destroy(sw) bind(C, name="vi_sweep_destroy")
      import :: c_ptr
      type(c_ptr) :: sw
    end subroutine
    !> a C string (vi_string converts it)
    type(c_ptr) function vi_sweep_errmsg(sw) bind(C, name="vi_sweep_errmsg")
      import :: c_ptr
      type(c_ptr), value :: sw
    end function
    integer(c_int) function vi_sweep_set_periods(sw, transient, record) &
        bind(C, name="vi_sweep_set_periods")
      import :: c_int, c_ptr
      type(c_ptr), value :: sw
      integer(c_int), value :: transient, record
    end function
    integer(c_int) function vi_sweep_set_classify(sw, tol, nmax) bind(C, name="vi_sweep_set_classify")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: sw
      real(c_double), value :: tol
      integer(c_int), value :: nmax
    end function
    integer(c_int) function vi_sweep_set_run(sw, method, rtol, atol) bind(C, name="vi_sweep_set_run")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: sw
      integer(c_int), value :: method
      real(c_double), value :: rtol, atol
    end function
    integer(c_int) function vi_sweep_set_initial(sw, t0, x, v) bind(C, name="vi_sweep_set_initial")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: sw
      real(c_double), value :: t0
      real(c_double), intent(in), optional :: x(*), v(*)
    end function
    integer(c_int) function vi_sweep_set_warm(sw, warm) bind(C, name="vi_sweep_set_warm")
      import :: c_int, c_ptr
      type(c_ptr), value :: sw
      integer(c_int), value :: warm
    end function
    integer(c_int) function vi_sweep_set_param(sw, key, val) bind(C, name="vi_sweep_set_param")
      import :: c_int, c_ptr, c_char, c_double
      type(c_ptr), value :: sw
      character(kind=c_char), intent(in) :: key(*)
      real(c_double), value :: val
    end function
    integer(c_int) function vi_sweep_param(sw, key, val) bind(C, name="vi_sweep_param")
      import :: c_int, c_ptr, c_char, c_double
      type(c_ptr), value :: sw
      character(kind=c_char), intent(in) :: key(*)
      real(c_double), intent(out) :: val
    end function
    integer(c_int) function vi_sweep_reset(sw) bind(C, name="vi_sweep_reset")
      import :: c_int, c_ptr
      type(c_ptr), value :: sw
    end function
    integer(c_int) function vi_sweep_warm_state(sw, x, v) bind(C, name="vi_sweep_warm_state")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: sw
      real(c_double), intent(out) :: x(*), v(*)
    end function
    integer(c_int) function vi_sweep_set_warm_state(sw, x, v) bind(C, name="vi_sweep_set_warm_state")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: sw
      real(c_double), intent(in) :: x(*), v(*)
    end function
    !> fn: integer(c_int) function f(sw, point, status, user) bind(C), all by value
    !> (sw a c_ptr, point integer(c_int64_t), status integer(c_int))
    integer(c_int) function vi_sweep_set_monitor(sw, fn, user, destroy) &
        bind(C, name="vi_sweep_set_monitor")
      import :: c_int, c_ptr, c_funptr
      type(c_ptr), value :: sw, user
      type(c_funptr), value :: fn, destroy
    end function
    !> fn: integer(c_int) function f(sim, user) bind(C), both type(c_ptr), value
    integer(c_int) function vi_sweep_set_sim_hook(sw, fn, user, destroy) &
        bind(C, name="vi_sweep_set_sim_hook")
      import :: c_int, c_ptr, c_funptr
      type(c_ptr), value :: sw, user
      type(c_funptr), value :: fn, destroy
    end function
    integer(c_int) function vi_sweep_set_cancel(sw, fn, user, destroy) &
        bind(C, name="vi_sweep_set_cancel")
      import :: c_int, c_ptr, c_funptr
      type(c_ptr), value :: sw, user
      type(c_funptr), value :: fn, destroy
    end function
    integer(c_int) function vi_sweep_set_orbits(sw, nphase) bind(C, name="vi_sweep_set_orbits")
      import :: c_int, c_ptr
      type(c_ptr), value :: sw
      integer(c_int), value :: nphase
    end function
    integer(c_int) function vi_sweep_set_lyapunov(sw, on) bind(C, name="vi_sweep_set_lyapunov")
      import :: c_int, c_ptr
      type(c_ptr), value :: sw
      integer(c_int), value :: on
    end function
    real(c_double) function vi_sweep_lyapunov(sw) bind(C, name="vi_sweep_lyapunov")
      import :: c_double, c_ptr
      type(c_ptr), value :: sw
    end function
    integer(c_int) function vi_sweep_iterate(sw) bind(C, name="vi_sweep_iterate")
      import :: c_int, c_ptr
      type(c_ptr), value :: sw
    end function
    integer(c_int) function vi_sweep_period(sw, n, m) bind(C, name="vi_sweep_period")
      import :: c_int, c_ptr
      type(c_ptr), value :: sw
      integer(c_int), intent(out) :: n, m
    end function
    integer(c_int) function vi_sweep_failed(sw) bind(C, name="vi_sweep_failed")
      import :: c_int, c_ptr
      type(c_ptr), value :: sw
    end function
    real(c_double) function vi_sweep_forcing_period(sw) bind(C, name="vi_sweep_forcing_period")
      import :: c_double, c_ptr
      type(c_ptr), value :: sw
    end function
    !> t, phase, vn receive C pointers to [count] arrays (c_f_pointer)
    integer(c_int) function vi_sweep_impacts(sw, count, t, phase, vn) &
        bind(C, name="vi_sweep_impacts")
      import :: c_int, c_ptr, c_int64_t
      type(c_ptr), value :: sw
      integer(c_int64_t), intent(out) :: count
      type(c_ptr), intent(out), optional :: t, phase, vn
    end function
    !> a C pointer to [ld x record] doubles (c_f_pointer)
    type(c_ptr) function vi_sweep_strobe(sw, ld, record) bind(C, name="vi_sweep_strobe")
      import :: c_ptr, c_int
      type(c_ptr), value :: sw
      integer(c_int), intent(out), optional :: ld, record
    end function
    integer(c_int) function vi_sweep_orbits(sw, count, vn, phase, stable, admissible) &
        bind(C, name="vi_sweep_orbits")
      import :: c_int, c_ptr
      type(c_ptr), value :: sw
      integer(c_int), intent(out) :: count
      type(c_ptr), intent(out), optional :: vn, phase, stable, admissible
    end function
    type(c_ptr) function vi_sweep_model(sw) bind(C, name="vi_sweep_model")
      import :: c_ptr
      type(c_ptr), value :: sw
    end function
    integer(c_int) function vi_sweep_attractors(count, ncoord, record, n, strobe, ld, tol, &
        id, nattr) bind(C, name="vi_sweep_attractors")
      import :: c_int, c_int64_t, c_double
      integer(c_int64_t), value :: count
      integer(c_int), value :: ncoord, record, ld
      integer(c_int), intent(in) :: n(*)
      real(c_double), intent(in) :: strobe(*)
      real(c_double), value :: tol
      integer(c_int), intent(out) :: id(*), nattr
    end function
    ! ---- continuation (vi_cont.h)
    integer(c_int) function vi_cont_create(model, key, n, method, out) bind(C, name="vi_cont_create")
      import :: c_int, c_ptr, c_char
      type(c_ptr), value :: model
      character(kind=c_char), intent(in) :: key(*)
      integer(c_int), value :: n, method
      type(c_ptr), intent(out) :: out
    end function
    subroutine vi_cont_destroy(c) bind(C, name="vi_cont_destroy")
      import :: c_ptr
      type(c_ptr) :: c
    end subroutine
    !> a C string (vi_string converts it)
    type(c_ptr) function vi_cont_errmsg(c) bind(C, name="vi_cont_errmsg")
      import :: c_ptr
      type(c_ptr), value :: c
    end function
    integer(c_int) function vi_cont_set_range(c, to, steps) bind(C, name="vi_cont_set_range")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: c
      real(c_double), value :: to
      integer(c_int), value :: steps
    end function
    integer(c_int) function vi_cont_set_orbit(c, t, x, v) bind(C, name="vi_cont_set_orbit")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: c
      real(c_double), value :: t
      real(c_double), intent(in) :: x(*), v(*)
    end function
    !> fn: integer(c_int) function f(c, point, user) bind(C), all by value
    integer(c_int) function vi_cont_set_monitor(c, fn, user, destroy) &
        bind(C, name="vi_cont_set_monitor")
      import :: c_int, c_ptr, c_funptr
      type(c_ptr), value :: c, user
      type(c_funptr), value :: fn, destroy
    end function
    !> fn: integer(c_int) function f(user) bind(C), user by value
    integer(c_int) function vi_cont_set_cancel(c, fn, user, destroy) &
        bind(C, name="vi_cont_set_cancel")
      import :: c_int, c_ptr, c_funptr
      type(c_ptr), value :: c, user
      type(c_funptr), value :: fn, destroy
    end function
    integer(c_int) function vi_cont_iterate(c) bind(C, name="vi_cont_iterate")
      import :: c_int, c_ptr
      type(c_ptr), value :: c
    end function
    integer(c_int) function vi_cont_done(c) bind(C, name="vi_cont_done")
      import :: c_int, c_ptr
      type(c_ptr), value :: c
    end function
    integer(c_int) function vi_cont_point(c, param, vn, t, rho, admissible) &
        bind(C, name="vi_cont_point")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: c
      real(c_double), intent(out), optional :: param, vn, t, rho
      integer(c_int), intent(out), optional :: admissible
    end function
    integer(c_int) function vi_cont_orbit(c, t, x, v) bind(C, name="vi_cont_orbit")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: c
      real(c_double), intent(out) :: t, x(*), v(*)
    end function
    integer(c_int) function vi_cont_num_events(c) bind(C, name="vi_cont_num_events")
      import :: c_int, c_ptr
      type(c_ptr), value :: c
    end function
    !> i is 0-based
    integer(c_int) function vi_cont_event(c, i, type, param, vn, re, im, admissible) &
        bind(C, name="vi_cont_event")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: c
      integer(c_int), value :: i
      integer(c_int), intent(out), optional :: type, admissible
      real(c_double), intent(out), optional :: param, vn, re, im
    end function
    ! ---- truncation study (vi_truncation.h); a row is
    ! ---- row(VI_TRUNCATION_COLUMNS), its k = 0 the reference
    integer(c_int) function vi_truncation_create(model, out) bind(C, name="vi_truncation_create")
      import :: c_int, c_ptr
      type(c_ptr), value :: model
      type(c_ptr), intent(out) :: out
    end function
    integer(c_int) function vi_truncation_create_fe(fe, out) bind(C, name="vi_truncation_create_fe")
      import :: c_int, c_ptr
      type(c_ptr), value :: fe
      type(c_ptr), intent(out) :: out
    end function
    subroutine vi_truncation_destroy(tr) bind(C, name="vi_truncation_destroy")
      import :: c_ptr
      type(c_ptr) :: tr
    end subroutine
    !> a C string (vi_string converts it)
    type(c_ptr) function vi_truncation_errmsg(tr) bind(C, name="vi_truncation_errmsg")
      import :: c_ptr
      type(c_ptr), value :: tr
    end function
    integer(c_int) function vi_truncation_set_modes(tr, lo, hi) bind(C, name="vi_truncation_set_modes")
      import :: c_int, c_ptr
      type(c_ptr), value :: tr
      integer(c_int), value :: lo, hi
    end function
    integer(c_int) function vi_truncation_set_initial(tr, t0, t_end, x, v) &
        bind(C, name="vi_truncation_set_initial")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: tr
      real(c_double), value :: t0, t_end
      real(c_double), intent(in), optional :: x(*), v(*)  ! absent: 0
    end function
    !> fn as for vi_sim_set_monitor
    integer(c_int) function vi_truncation_set_monitor(tr, fn, user, destroy) &
        bind(C, name="vi_truncation_set_monitor")
      import :: c_int, c_ptr, c_funptr
      type(c_ptr), value :: tr, user
      type(c_funptr), value :: fn, destroy
    end function
    !> fn: integer(c_int) function f(user) bind(C), user by value
    integer(c_int) function vi_truncation_set_cancel(tr, fn, user, destroy) &
        bind(C, name="vi_truncation_set_cancel")
      import :: c_int, c_ptr, c_funptr
      type(c_ptr), value :: tr, user
      type(c_funptr), value :: fn, destroy
    end function
    integer(c_int) function vi_truncation_iterate(tr) bind(C, name="vi_truncation_iterate")
      import :: c_int, c_ptr
      type(c_ptr), value :: tr
    end function
    integer(c_int) function vi_truncation_done(tr) bind(C, name="vi_truncation_done")
      import :: c_int, c_ptr
      type(c_ptr), value :: tr
    end function
    integer(c_int) function vi_truncation_row(tr, k, row) bind(C, name="vi_truncation_row")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: tr
      integer(c_int), value :: k
      real(c_double), intent(out) :: row(*)
    end function
    !> rows(ldrows, VI_TRUNCATION_COLUMNS); rows absent: only nrows
    integer(c_int) function vi_truncation_table(tr, rows, ldrows, nrows) &
        bind(C, name="vi_truncation_table")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: tr
      real(c_double), intent(out), optional :: rows(*)
      integer(c_int), value :: ldrows
      integer(c_int), intent(out) :: nrows
    end function
    integer(c_int) function vi_truncation_summary(tr, info) bind(C, name="vi_truncation_summary")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: tr
      real(c_double), intent(out) :: info(*)
    end function
    !> the reference model: a view owned by the study
    type(c_ptr) function vi_truncation_model(tr) bind(C, name="vi_truncation_model")
      import :: c_ptr
      type(c_ptr), value :: tr
    end function
    ! ---- two-parameter curves (vi_cont_curve.h)
    integer(c_int) function vi_cont_refine(model, key, n, kind, p, t, x, v) &
        bind(C, name="vi_cont_refine")
      import :: c_int, c_ptr, c_char, c_double
      type(c_ptr), value :: model
      character(kind=c_char), intent(in) :: key(*)
      integer(c_int), value :: n, kind
      real(c_double), intent(inout) :: p, t, x(*), v(*)
    end function
    integer(c_int) function vi_cont_refine_pnm(model, key, n, m, kind, p, t, x, v, ld) &
        bind(C, name="vi_cont_refine_pnm")
      import :: c_int, c_ptr, c_char, c_double
      type(c_ptr), value :: model
      character(kind=c_char), intent(in) :: key(*)
      integer(c_int), value :: n, m, kind, ld
      real(c_double), intent(inout) :: p, t(*), x(*), v(*)
    end function
    integer(c_int) function vi_cont_curve_create(model, kind, n, m, key, key2, out) &
        bind(C, name="vi_cont_curve_create")
      import :: c_int, c_ptr, c_char
      type(c_ptr), value :: model
      integer(c_int), value :: kind, n, m
      character(kind=c_char), intent(in) :: key(*), key2(*)
      type(c_ptr), intent(out) :: out
    end function
    subroutine vi_cont_curve_destroy(c) bind(C, name="vi_cont_curve_destroy")
      import :: c_ptr
      type(c_ptr) :: c
    end subroutine
    !> a C string (vi_string converts it)
    type(c_ptr) function vi_cont_curve_errmsg(c) bind(C, name="vi_cont_curve_errmsg")
      import :: c_ptr
      type(c_ptr), value :: c
    end function
    integer(c_int) function vi_cont_curve_set_orbit(c, t, x, v) &
        bind(C, name="vi_cont_curve_set_orbit")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: c
      real(c_double), value :: t
      real(c_double), intent(in) :: x(*), v(*)
    end function
    !> t(mi), x, v(ld, mi): the impacts of a P(n, mi) orbit
    integer(c_int) function vi_cont_curve_set_impacts(c, t, x, v, ld) &
        bind(C, name="vi_cont_curve_set_impacts")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: c
      real(c_double), intent(in) :: t(*), x(*), v(*)
      integer(c_int), value :: ld
    end function
    integer(c_int) function vi_cont_curve_locate(c, to, steps, param) &
        bind(C, name="vi_cont_curve_locate")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: c
      real(c_double), value :: to
      integer(c_int), value :: steps
      real(c_double), intent(out), optional :: param
    end function
    integer(c_int) function vi_cont_curve_set_range(c, from2, to2, steps) &
        bind(C, name="vi_cont_curve_set_range")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: c
      real(c_double), value :: from2, to2
      integer(c_int), value :: steps
    end function
    integer(c_int) function vi_cont_curve_iterate(c) bind(C, name="vi_cont_curve_iterate")
      import :: c_int, c_ptr
      type(c_ptr), value :: c
    end function
    integer(c_int) function vi_cont_curve_done(c) bind(C, name="vi_cont_curve_done")
      import :: c_int, c_ptr
      type(c_ptr), value :: c
    end function
    integer(c_int) function vi_cont_curve_start(c) bind(C, name="vi_cont_curve_start")
      import :: c_int, c_ptr
      type(c_ptr), value :: c
    end function
    integer(c_int) function vi_cont_curve_point(c, p, p2, t, x, v, rho) &
        bind(C, name="vi_cont_curve_point")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: c
      real(c_double), intent(out), optional :: p, p2, t, x(*), v(*), rho
    end function
    integer(c_int) function vi_cont_curve_impacts(c, t, x, v, ld) &
        bind(C, name="vi_cont_curve_impacts")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: c
      real(c_double), intent(out), optional :: t(*), x(*), v(*)
      integer(c_int), value :: ld
    end function
    integer(c_int) function vi_cont_curve_num_special(c) &
        bind(C, name="vi_cont_curve_num_special")
      import :: c_int, c_ptr
      type(c_ptr), value :: c
    end function
    !> i is 0-based
    integer(c_int) function vi_cont_curve_special(c, i, type, p, p2, located) &
        bind(C, name="vi_cont_curve_special")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: c
      integer(c_int), value :: i
      integer(c_int), intent(out), optional :: type, located
      real(c_double), intent(out), optional :: p, p2
    end function
    ! ---- the orbit census (vi_census.h)
    integer(c_int) function vi_census_create(model, n, m, out) bind(C, name="vi_census_create")
      import :: c_int, c_ptr
      type(c_ptr), value :: model
      integer(c_int), value :: n, m
      type(c_ptr), intent(out) :: out
    end function
    subroutine vi_census_destroy(c) bind(C, name="vi_census_destroy")
      import :: c_ptr
      type(c_ptr) :: c
    end subroutine
    !> a C string (vi_string converts it)
    type(c_ptr) function vi_census_errmsg(c) bind(C, name="vi_census_errmsg")
      import :: c_ptr
      type(c_ptr), value :: c
    end function
    integer(c_int) function vi_census_set_phases(c, nphase) bind(C, name="vi_census_set_phases")
      import :: c_int, c_ptr
      type(c_ptr), value :: c
      integer(c_int), value :: nphase
    end function
    integer(c_int) function vi_census_set_initial(c, t0, x, v) bind(C, name="vi_census_set_initial")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: c
      real(c_double), value :: t0
      real(c_double), intent(in), optional :: x(*), v(*)
    end function
    !> fn: integer(c_int) function f(sim, user) bind(C), both type(c_ptr), value
    integer(c_int) function vi_census_set_sim_hook(c, fn, user, destroy) &
        bind(C, name="vi_census_set_sim_hook")
      import :: c_int, c_ptr, c_funptr
      type(c_ptr), value :: c, user
      type(c_funptr), value :: fn, destroy
    end function
    !> fn: integer(c_int) function f(c, index, user) bind(C), all by value
    !> (c a c_ptr, index integer(c_int), 0-based)
    integer(c_int) function vi_census_set_monitor(c, fn, user, destroy) &
        bind(C, name="vi_census_set_monitor")
      import :: c_int, c_ptr, c_funptr
      type(c_ptr), value :: c, user
      type(c_funptr), value :: fn, destroy
    end function
    integer(c_int) function vi_census_set_cancel(c, fn, user, destroy) &
        bind(C, name="vi_census_set_cancel")
      import :: c_int, c_ptr, c_funptr
      type(c_ptr), value :: c, user
      type(c_funptr), value :: fn, destroy
    end function
    integer(c_int) function vi_census_run(c) bind(C, name="vi_census_run")
      import :: c_int, c_ptr
      type(c_ptr), value :: c
    end function
    integer(c_int) function vi_census_count(c) bind(C, name="vi_census_count")
      import :: c_int, c_ptr
      type(c_ptr), value :: c
    end function
    !> i is 0-based, stop receives 0-based stops; x, v are [ld x m]
    integer(c_int) function vi_census_orbit(c, i, t, x, v, ld, stop, vn) &
        bind(C, name="vi_census_orbit")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: c
      integer(c_int), value :: i, ld
      real(c_double), intent(out), optional :: t(*), x(*), v(*), vn(*)
      integer(c_int), intent(out), optional :: stop(*)
    end function
    !> i is 0-based; re, im are [2n]
    integer(c_int) function vi_census_stability(c, i, re, im, stable, admissible, gmax) &
        bind(C, name="vi_census_stability")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: c
      integer(c_int), value :: i
      real(c_double), intent(out), optional :: re(*), im(*), gmax
      integer(c_int), intent(out), optional :: stable, admissible
    end function

    ! ---- finite-element structures in (vi_sparse.h) --------------------------
    ! CSC arrays pass unchanged with base = 1; dof indices (vi_fe_add_stop_dof,
    ! vi_fe_set_outputs, vi_fe_set_host_modes' rows) are 0-based: subtract 1.
    integer(c_int) function vi_fe_create(n, fe) bind(C, name="vi_fe_create")
      import :: c_int, c_ptr
      integer(c_int), value :: n
      type(c_ptr) :: fe
    end function
    subroutine vi_fe_destroy(fe) bind(C, name="vi_fe_destroy")
      import :: c_ptr
      type(c_ptr) :: fe
    end subroutine
    type(c_ptr) function vi_fe_errmsg(fe) bind(C, name="vi_fe_errmsg")
      import :: c_ptr
      type(c_ptr), value :: fe
    end function
    integer(c_int) function vi_fe_set_mass_csc(fe, storage, base, colptr, rowind, values) &
        bind(C, name="vi_fe_set_mass_csc")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: fe
      integer(c_int), value :: storage, base
      integer(c_int), intent(in) :: colptr(*), rowind(*)
      real(c_double), intent(in) :: values(*)
    end function
    integer(c_int) function vi_fe_set_stiffness_csc(fe, storage, base, colptr, rowind, values) &
        bind(C, name="vi_fe_set_stiffness_csc")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: fe
      integer(c_int), value :: storage, base
      integer(c_int), intent(in) :: colptr(*), rowind(*)
      real(c_double), intent(in) :: values(*)
    end function
    integer(c_int) function vi_fe_set_damping_csc(fe, storage, base, colptr, rowind, values) &
        bind(C, name="vi_fe_set_damping_csc")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: fe
      integer(c_int), value :: storage, base
      integer(c_int), intent(in), optional :: colptr(*), rowind(*)  ! absent: C = 0
      real(c_double), intent(in), optional :: values(*)
    end function
    integer(c_int) function vi_fe_set_rayleigh(fe, alpha, beta) bind(C, name="vi_fe_set_rayleigh")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: fe
      real(c_double), value :: alpha, beta
    end function
    integer(c_int) function vi_fe_set_modal_damping(fe, nzeta, zeta) &
        bind(C, name="vi_fe_set_modal_damping")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: fe
      integer(c_int), value :: nzeta
      real(c_double), intent(in) :: zeta(*)
    end function
    integer(c_int) function vi_fe_set_modes(fe, k) bind(C, name="vi_fe_set_modes")
      import :: c_int, c_ptr
      type(c_ptr), value :: fe
      integer(c_int), value :: k
    end function
    integer(c_int) function vi_fe_set_rigid_modes(fe, count) &
        bind(C, name="vi_fe_set_rigid_modes")
      import :: c_int, c_ptr
      type(c_ptr), value :: fe
      integer(c_int), value :: count
    end function
    integer(c_int) function vi_fe_set_accuracy(fe, tol) bind(C, name="vi_fe_set_accuracy")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: fe
      real(c_double), value :: tol
    end function
    integer(c_int) function vi_fe_summary(fe, massless, rigid, rule, orthogonality) &
        bind(C, name="vi_fe_summary")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: fe
      integer(c_int), optional :: massless, rigid, rule
      real(c_double), optional :: orthogonality
    end function
    type(c_ptr) function vi_fe_mode_residuals(fe) bind(C, name="vi_fe_mode_residuals")
      import :: c_ptr
      type(c_ptr), value :: fe
    end function
    type(c_ptr) function vi_fe_mode_rigidity(fe) bind(C, name="vi_fe_mode_rigidity")
      import :: c_ptr
      type(c_ptr), value :: fe
    end function
    integer(c_int) function vi_fe_set_shift(fe, sigma) bind(C, name="vi_fe_set_shift")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: fe
      real(c_double), value :: sigma
    end function
    integer(c_int) function vi_fe_set_eigensolver(fe, tol, ncv, maxit) &
        bind(C, name="vi_fe_set_eigensolver")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: fe
      real(c_double), value :: tol
      integer(c_int), value :: ncv, maxit
    end function
    integer(c_int) function vi_fe_set_memory_limit(fe, bytes) bind(C, name="vi_fe_set_memory_limit")
      import :: c_int, c_ptr, c_int64_t
      type(c_ptr), value :: fe
      integer(c_int64_t), value :: bytes
    end function
    integer(c_int) function vi_fe_set_host_modes(fe, k, omega, zeta, D, ldd, nrows, rows, Psi, ldp) &
        bind(C, name="vi_fe_set_host_modes")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: fe
      integer(c_int), value :: k, ldd, nrows, ldp
      real(c_double), intent(in) :: omega(*)
      real(c_double), intent(in), optional :: zeta(*), D(ldd, *)
      integer(c_int), intent(in) :: rows(*)       ! 0-based dofs
      real(c_double), intent(in) :: Psi(ldp, *)
    end function
    integer(c_int) function vi_fe_add_stop(fe, w, x_s, r) bind(C, name="vi_fe_add_stop")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: fe
      real(c_double), intent(in) :: w(*)
      real(c_double), value :: x_s, r
    end function
    integer(c_int) function vi_fe_add_stop_dof(fe, dof, direction, x_s, r) &
        bind(C, name="vi_fe_add_stop_dof")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: fe
      integer(c_int), value :: dof, direction     ! dof 0-based
      real(c_double), value :: x_s, r
    end function
    integer(c_int) function vi_fe_set_forcing(fe, omega, a, b, f0) bind(C, name="vi_fe_set_forcing")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: fe
      real(c_double), value :: omega
      real(c_double), intent(in), optional :: a(*), b(*), f0(*)
    end function
    integer(c_int) function vi_fe_set_outputs(fe, nout, dofs) bind(C, name="vi_fe_set_outputs")
      import :: c_int, c_ptr
      type(c_ptr), value :: fe
      integer(c_int), value :: nout
      integer(c_int), intent(in), optional :: dofs(*)  ! 0-based
    end function
    integer(c_int) function vi_fe_set_keep_shapes(fe, keep) bind(C, name="vi_fe_set_keep_shapes")
      import :: c_int, c_ptr
      type(c_ptr), value :: fe
      integer(c_int), value :: keep
    end function
    integer(c_int) function vi_fe_setup(fe) bind(C, name="vi_fe_setup")
      import :: c_int, c_ptr
      type(c_ptr), value :: fe
    end function
    integer(c_int) function vi_fe_create_model(fe, model) bind(C, name="vi_fe_create_model")
      import :: c_int, c_ptr
      type(c_ptr), value :: fe
      type(c_ptr) :: model
    end function
    integer(c_int) function vi_fe_n(fe) bind(C, name="vi_fe_n")
      import :: c_int, c_ptr
      type(c_ptr), value :: fe
    end function
    integer(c_int) function vi_fe_num_modes(fe) bind(C, name="vi_fe_num_modes")
      import :: c_int, c_ptr
      type(c_ptr), value :: fe
    end function
    type(c_ptr) function vi_fe_omega(fe) bind(C, name="vi_fe_omega")
      import :: c_ptr
      type(c_ptr), value :: fe
    end function
    type(c_ptr) function vi_fe_modal_damping(fe, ld) bind(C, name="vi_fe_modal_damping")
      import :: c_ptr, c_int
      type(c_ptr), value :: fe
      integer(c_int), optional :: ld
    end function
    type(c_ptr) function vi_fe_modal_stops(fe, ld) bind(C, name="vi_fe_modal_stops")
      import :: c_ptr, c_int
      type(c_ptr), value :: fe
      integer(c_int), optional :: ld
    end function
    integer(c_int) function vi_fe_num_stops(fe) bind(C, name="vi_fe_num_stops")
      import :: c_int, c_ptr
      type(c_ptr), value :: fe
    end function
    type(c_ptr) function vi_fe_output_shapes(fe, ld) bind(C, name="vi_fe_output_shapes")
      import :: c_ptr, c_int
      type(c_ptr), value :: fe
      integer(c_int), optional :: ld
    end function
    type(c_ptr) function vi_fe_shapes(fe, ld) bind(C, name="vi_fe_shapes")
      import :: c_ptr, c_int
      type(c_ptr), value :: fe
      integer(c_int), optional :: ld
    end function
    real(c_double) function vi_fe_shift(fe) bind(C, name="vi_fe_shift")
      import :: c_double, c_ptr
      type(c_ptr), value :: fe
    end function
    real(c_double) function vi_fe_residual(fe) bind(C, name="vi_fe_residual")
      import :: c_double, c_ptr
      type(c_ptr), value :: fe
    end function
    integer(c_int) function vi_fe_stop_compliance(fe, s, dynamic, statik) &
        bind(C, name="vi_fe_stop_compliance")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: fe
      integer(c_int), value :: s
      real(c_double), optional :: dynamic, statik
    end function
    integer(c_int) function vi_fe_matrix_csc(fe, which, nnz, colptr, rowind, values) &
        bind(C, name="vi_fe_matrix_csc")
      import :: c_int, c_ptr
      type(c_ptr), value :: fe
      integer(c_int), value :: which
      integer(c_int), optional :: nnz
      type(c_ptr), optional :: colptr, rowind, values  ! views: c_f_pointer
    end function
    integer(c_int) function vi_fe_to_outputs(fe, ncol, Q, ldq, Y, ldy) bind(C, name="vi_fe_to_outputs")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: fe
      integer(c_int), value :: ncol, ldq, ldy
      real(c_double), intent(in) :: Q(ldq, *)
      real(c_double) :: Y(ldy, *)
    end function
    integer(c_int) function vi_fe_to_modal(fe, x, q) bind(C, name="vi_fe_to_modal")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: fe
      real(c_double), intent(in) :: x(*)
      real(c_double) :: q(*)
    end function
    integer(c_int) function vi_fe_memory_estimate(n, nnz, k, keep, bytes) &
        bind(C, name="vi_fe_memory_estimate")
      import :: c_int, c_int64_t
      integer(c_int), value :: n, k, keep
      integer(c_int64_t), value :: nnz
      integer(c_int64_t) :: bytes
    end function
    integer(c_int) function vi_model_create_modal(k, omega, zeta, D, ldd, model) &
        bind(C, name="vi_model_create_modal")
      import :: c_int, c_ptr, c_double
      integer(c_int), value :: k, ldd
      real(c_double), intent(in) :: omega(*)
      real(c_double), intent(in), optional :: zeta(*), D(ldd, *)
      type(c_ptr) :: model
    end function
  end interface

contains

  !> A C string (as returned by vi_strerror, vi_*_errmsg, ...) as a Fortran
  !> string; '' for a null pointer.
  function vi_string(p) result(s)
    type(c_ptr), intent(in) :: p
    character(len=:), allocatable :: s
    character(kind=c_char), pointer :: chars(:)
    integer :: n
    interface
      integer(c_size_t) function c_strlen(str) bind(C, name="strlen")
        import :: c_size_t, c_ptr
        type(c_ptr), value :: str
      end function
    end interface
    if (.not. c_associated(p)) then
      s = ''
      return
    end if
    n = int(c_strlen(p))
    call c_f_pointer(p, chars, [n])
    allocate(character(len=n) :: s)
    s = transfer(chars(1:n), s)
  end function
end module vibroimpact
