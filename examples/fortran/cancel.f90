! cancel.f90 - a scene, a monitor and a cancellation callback from Fortran.
!
!   vi_cancel_fortran            the embedded Fig. 2 scene
!   vi_cancel_fortran FILE.yaml  another scene
!
! The run is cancelled after half of its impacts by a flag, the way a
! SIGINT handler would set it, and then resumed to the end: a cancelled
! vi_sim_run keeps the state of its last completed step, so the two halves
! give the same impacts as one uninterrupted run (one per forcing period on
! Fig. 2's P(1,1) orbit: 100 in 100 periods).  A second simulation is
! then driven impact by impact (vi_sim_run_to_event), as a host code
! would, and meets the same first impacts.  It also checks that the
! bind(C) types have the C layout and that a bad scene comes back with a
! diagnostic naming the key.  Exits 1 on any failure.
module cancel_callbacks
  use, intrinsic :: iso_c_binding
  use vibroimpact
  implicit none
  integer :: impacts = 0, polls = 0, monitor_calls = 0, cancel_after = 50
  logical :: stop_flag = .false.
  real(c_double) :: t_impact(10) = 0  ! the first impact times
contains
  integer(c_int) function on_event(ev, user) bind(C)
    type(vi_event), intent(in) :: ev
    type(c_ptr), value :: user
    on_event = merge(1, 0, c_associated(user))
    if (ev%kind /= VI_EVENT_IMPACT) return
    impacts = impacts + 1
    if (impacts <= size(t_impact)) t_impact(impacts) = ev%t
    if (impacts == cancel_after) stop_flag = .true.  ! as a signal handler would
  end function
  ! polled at every step: cheap, reads the flag only
  integer(c_int) function on_cancel(user) bind(C)
    type(c_ptr), value :: user
    polls = polls + 1
    on_cancel = merge(1, 0, stop_flag .or. c_associated(user))
  end function
  integer(c_int) function on_progress(p, user) bind(C)
    type(vi_progress), intent(in) :: p
    type(c_ptr), value :: user
    monitor_calls = monitor_calls + 1
    if (mod(monitor_calls, 25) == 0) print '(a,f9.3,a,f9.3,a,i0,a)', '   progress: t = ', p%t, &
        ' of ', p%t_end, ' (', p%impacts, ' impacts)'
    on_progress = merge(1, 0, c_associated(user))
  end function
end module cancel_callbacks

program cancel
  use, intrinsic :: iso_c_binding
  use vibroimpact
  use vibroimpact_io
  use cancel_callbacks
  implicit none
  type(c_ptr) :: scene = c_null_ptr, model = c_null_ptr, sim = c_null_ptr
  type(vi_diag) :: diag
  type(vi_event) :: ev
  type(vi_progress) :: pr
  type(vi_ledger_interval) :: iv
  character(len=512) :: path
  character(kind=c_char) :: buf(1024)
  integer(c_int) :: st, j, kind
  real(c_double) :: t, t_end, period
  integer :: failures = 0

  ! the bind(C) types have the sizes of the C structs
  call check(c_sizeof(ev) == VI_C_SIZEOF_EVENT, 'vi_event layout')
  call check(c_sizeof(pr) == VI_C_SIZEOF_PROGRESS, 'vi_progress layout')
  call check(c_sizeof(iv) == VI_C_SIZEOF_LEDGER_INTERVAL, 'vi_ledger_interval layout')
  call check(c_sizeof(diag) == VI_C_SIZEOF_DIAG, 'vi_diag layout')

  ! a bad scene: the diagnostic names the key
  st = vi_scene_parse('model: {chain: {n: 1, m: 1.0, k: 1.0}}'//c_new_line// &
                      'stop: {mass: 1, xs: 0.1, r: 2.0}'//c_null_char, -1_c_long, &
                      'bad.yaml'//c_null_char, scene, diag)
  call vi_diag_format(diag, buf, size(buf, kind=c_int))
  print '(a)', ' bad scene: '//vi_chars(buf)
  call check(st < 0 .and. diag%code == st .and. .not. c_associated(scene), 'bad scene rejected')
  call check(vi_chars(diag%file) == 'bad.yaml' .and. vi_chars(diag%key) == 'stop.r' &
             .and. diag%line == 2 .and. st == VI_ERR_RESTITUTION, 'diag names file, line and key')

  if (command_argument_count() >= 1) then
    call get_command_argument(1, path)
    st = vi_scene_load(trim(path)//c_null_char, scene, diag)
  else
    st = vi_scene_parse(vi_string(vi_scene_default_text())//c_null_char, -1_c_long, &
                        'fig2.yaml'//c_null_char, scene, diag)
  end if
  if (st == VI_OK) st = vi_scene_create_model(scene, model, diag)
  if (st == VI_OK) st = vi_sim_create(model, sim)
  if (st == VI_OK) st = vi_scene_configure_sim(scene, sim, diag)
  if (st /= VI_OK) then
    call vi_diag_format(diag, buf, size(buf, kind=c_int))
    print '(a)', ' scene: '//vi_chars(buf)
    stop 1
  end if
  t_end = vi_scene_t_end(scene)
  period = 2 * acos(-1.0_c_double) / vi_model_omega_forcing(model)
  print '(a,a,a,i0,a,f9.4)', ' scene ', vi_string(vi_scene_name(scene)), ': n = ', &
      vi_scene_n(scene), ', t_end = ', t_end

  st = vi_sim_set_event_callback(sim, c_funloc(on_event), c_null_ptr, c_null_funptr)
  if (st == VI_OK) st = vi_sim_set_cancel(sim, c_funloc(on_cancel), c_null_ptr, c_null_funptr)
  if (st == VI_OK) st = vi_sim_set_monitor(sim, period, c_funloc(on_progress), c_null_ptr, &
                                           c_null_funptr)
  call check(st == VI_OK, 'callbacks set')

  st = vi_sim_run(sim, t_end)
  if (vi_sim_state(sim, t) /= VI_OK) stop 1
  print '(a,a,a,f9.4,a,i0,a)', ' first run: ', vi_string(vi_status_name(st)), ' at t = ', t, &
      ' after ', impacts, ' impacts'
  call check(st == VI_CANCELLED, 'the flag cancels the run')
  call check(impacts == cancel_after, 'cancelled right after the flagged impact')
  call check(t < t_end, 'cancelled before the end')

  stop_flag = .false.
  st = vi_sim_run(sim, t_end)
  if (vi_sim_state(sim, t) /= VI_OK) stop 1
  print '(a,a,a,f9.4,a,i0,a,i0,a)', ' resumed: ', vi_string(vi_status_name(st)), ' at t = ', t, &
      ', ', impacts, ' impacts, ', polls, ' cancellation polls'
  call check(st == VI_OK .and. abs(t - t_end) <= 1e-9_c_double * t_end, 'resumed to the end')
  call check(vi_sim_stat(sim, VI_STAT_IMPACTS) == impacts, 'impacts counted once')
  if (command_argument_count() == 0) call check(impacts == 100, 'Fig. 2: 100 impacts')
  call check(monitor_calls >= int(t_end / period) - 1, 'monitor once per period')

  print '(a,a,a,a)', ' method: ', vi_string(vi_method_name(vi_sim_method_used(sim))), '; ', &
      vi_string(vi_sim_method_note(sim))
  call check(vi_method_from_name('exact'//c_null_char) == VI_METHOD_EXACT, 'method names')
  do j = 0, VI_STAT_COUNT - 1
    print '(3x,a18,i10)', vi_string(vi_stat_name(j)), vi_sim_stat(sim, j)
  end do

  ! impact by impact: the host drives, the same impacts come out
  call vi_sim_destroy(sim)
  st = vi_sim_create(model, sim)
  if (st == VI_OK) st = vi_scene_configure_sim(scene, sim, diag)
  if (st == VI_OK) st = vi_sim_setup(sim)  ! allocation errors surface here
  call check(st == VI_OK, 'second sim set up')
  do j = 1, size(t_impact)
    st = vi_sim_run_to_event(sim, t_end, kind)
    if (st /= VI_OK .or. kind /= VI_EVENT_IMPACT) exit
    if (vi_sim_state(sim, t) /= VI_OK) stop 1
    ! the state after the event has the event's time; same integrator, same steps
    call check(abs(t - t_impact(j)) <= 1e-9_c_double * t_impact(j), 'stepped impact time')
  end do
  print '(a,i0,a,f12.8)', ' stepped: ', j - 1, ' impacts one call each, the last at t = ', t
  call check(j - 1 == size(t_impact), 'ten impacts stepped')

  call vi_sim_destroy(sim)
  call vi_model_destroy(model)
  call vi_scene_destroy(scene)
  call check(.not. (c_associated(sim) .or. c_associated(model) .or. c_associated(scene)), &
             'destroy clears the handles')
  if (failures > 0) stop 1
  print '(a)', ' ok'
contains
  subroutine check(cond, what)
    logical, intent(in) :: cond
    character(len=*), intent(in) :: what
    if (.not. cond) then
      print '(a)', ' FAIL: '//what
      failures = failures + 1
    end if
  end subroutine
end program cancel
