! vibroimpact_io.f90 - Fortran 2003 interface to the companion libraries
! vibroimpact_scene (YAML scene files, scene edits, Matrix Market files,
! output paths: vi_scene.h, vi_scene_edit.h, vi_mmio.h, vi_output.h) and
! vibroimpact_h5 (HDF5 output: vi_writer.h, vi_truncation_io.h,
! vi_identify_io.h).
!
!   use vibroimpact
!   use vibroimpact_io        ! and link -lvibroimpact_scene (vibroimpact::scene),
!                             ! with -lvibroimpact_h5 (vibroimpact::h5) for HDF5
!
! It holds interfaces (and vi_chars) only, so the Fortran library itself needs no HDF5 or
! YAML: a program that uses none of these routines links as before.
! Conventions as in module vibroimpact; strings into C end with c_null_char.
module vibroimpact_io
  use, intrinsic :: iso_c_binding
  ! the truncation table's sizes, declared with the study (vi_truncation.h)
  ! and still reachable from this module, as before
  use vibroimpact, only: vi_event, vi_ledger_interval, VI_TRUNCATION_COLUMNS, &
                         VI_TRUNCATION_INFO
  implicit none
  private

  include 'vi_io_constants.inc'

  !> Where and why a scene failed (vi_diag in vi_scene.h); the texts are
  !> NUL-terminated character arrays: read them with vi_chars.
  type, bind(C), public :: vi_diag
    integer(c_int) :: code, line, column
    character(kind=c_char) :: file(VI_DIAG_FILE_LEN)
    character(kind=c_char) :: key(VI_DIAG_KEY_LEN)
    character(kind=c_char) :: value(VI_DIAG_VALUE_LEN)
    character(kind=c_char) :: message(VI_DIAG_MESSAGE_LEN)
  end type

  public :: vi_chars
  public :: vi_scene_load, vi_scene_parse, vi_scene_destroy, vi_scene_create_model, &
            vi_scene_configure_sim, vi_scene_name, vi_scene_text, vi_scene_n, &
            vi_scene_t0, vi_scene_t_end, vi_scene_rtol, vi_scene_atol, &
            vi_scene_method, vi_scene_samples_per_period, vi_scene_outputs, &
            vi_scene_set_run, vi_diag_format, vi_scene_default_text, &
            vi_scene_load_limited, vi_scene_parse_limited, vi_scene_load_within, &
            vi_scene_memory_estimate, vi_scene_memory_available, &
            vi_scene_check_memory, vi_scene_dofs, &
            vi_scene_fe_summary, &
            vi_scene_create_fe, vi_scene_initial, &
            vi_scene_param_key
  public :: vi_scene_edit_create, vi_scene_edit_create_limited, &
            vi_scene_edit_destroy, vi_scene_edit_set, &
            vi_scene_edit_assign, vi_scene_edit_set_number, vi_scene_edit_get, &
            vi_scene_edit_text, vi_scene_edit_parse, vi_scene_edit_parse_within
  public :: vi_identify_write_h5
  public :: vi_truncation_write_h5, VI_TRUNCATION_COLUMNS, VI_TRUNCATION_INFO
  public :: vi_writer_create, vi_writer_write_header, vi_writer_event, &
            vi_writer_sample, vi_writer_ledger, vi_writer_orbit, vi_writer_rows, &
            vi_writer_close, vi_writer_abort, vi_writer_errmsg, &
            vi_output_resolve, vi_writer_run_info, vi_writer_finish, vi_writer_fe_shapes, &
            vi_output_check, vi_output_part, vi_output_same, vi_output_open, &
            vi_output_close, vi_output_discard, vi_output_commit
  public :: vi_mm_read_header, vi_mm_load, vi_mm_load_limited, vi_mm_destroy, &
            vi_mm_rows, vi_mm_cols, vi_mm_nnz, vi_mm_storage_kind, vi_mm_colptr, &
            vi_mm_rowind, vi_mm_values
  public :: vi_matrix_detect, vi_matrix_read_header, vi_matrix_load, &
            vi_dofmap_scan, vi_dofmap_destroy, vi_dofmap_n, vi_dofmap_label, &
            vi_dofmap_index, vi_scene_dofmap, vi_scene_matrix_format

  interface
    ! ---- scenes ---------------------------------------------------------------
    !> path: 'scene.yaml'//c_null_char; diag optional
    integer(c_int) function vi_scene_load(path, scene, diag) bind(C, name="vi_scene_load")
      import :: c_int, c_ptr, c_char, vi_diag
      character(kind=c_char), intent(in) :: path(*)
      type(c_ptr) :: scene
      type(vi_diag), optional :: diag
    end function
    !> text: a C string (len < 0) or len characters; name: C string
    integer(c_int) function vi_scene_parse(text, len, name, scene, diag) bind(C, name="vi_scene_parse")
      import :: c_int, c_int64_t, c_ptr, c_char, vi_diag
      character(kind=c_char), intent(in) :: text(*), name(*)
      integer(c_int64_t), value :: len
      type(c_ptr) :: scene
      type(vi_diag), optional :: diag
    end function
    !> max_bytes <= 0, max_depth <= 0: the defaults (VI_SCENE_MAX_BYTES, _DEPTH)
    integer(c_int) function vi_scene_load_limited(path, max_bytes, max_depth, scene, diag) &
        bind(C, name="vi_scene_load_limited")
      import :: c_int, c_int64_t, c_ptr, c_char, vi_diag
      character(kind=c_char), intent(in) :: path(*)
      integer(c_int64_t), value :: max_bytes
      integer(c_int), value :: max_depth
      type(c_ptr) :: scene
      type(vi_diag), optional :: diag
    end function
    !> max_memory: the budget in bytes the scene's vectors of n must fit (<= 0:
    !> what the machine has), checked before they are allocated
    integer(c_int) function vi_scene_load_within(path, max_bytes, max_depth, max_memory, &
        scene, diag) bind(C, name="vi_scene_load_within")
      import :: c_int, c_int64_t, c_double, c_ptr, c_char, vi_diag
      character(kind=c_char), intent(in) :: path(*)
      integer(c_int64_t), value :: max_bytes
      integer(c_int), value :: max_depth
      real(c_double), value :: max_memory
      type(c_ptr) :: scene
      type(vi_diag), optional :: diag
    end function
    integer(c_int) function vi_scene_parse_limited(text, len, name, max_depth, scene, diag) &
        bind(C, name="vi_scene_parse_limited")
      import :: c_int, c_int64_t, c_ptr, c_char, vi_diag
      character(kind=c_char), intent(in) :: text(*), name(*)
      integer(c_int64_t), value :: len
      integer(c_int), value :: max_depth
      type(c_ptr) :: scene
      type(vi_diag), optional :: diag
    end function
    real(c_double) function vi_scene_memory_estimate(scene) bind(C, name="vi_scene_memory_estimate")
      import :: c_double, c_ptr
      type(c_ptr), value :: scene
    end function
    real(c_double) function vi_scene_memory_available() bind(C, name="vi_scene_memory_available")
      import :: c_double
    end function
    !> max_bytes <= 0: MemAvailable of /proc/meminfo
    integer(c_int) function vi_scene_check_memory(scene, max_bytes, diag) bind(C, name="vi_scene_check_memory")
      import :: c_int, c_double, c_ptr, vi_diag
      type(c_ptr), value :: scene
      real(c_double), value :: max_bytes
      type(vi_diag), optional :: diag
    end function
    ! ---- --set overrides (vi_scene_edit.h); keys and values end in c_null_char
    integer(c_int) function vi_scene_edit_create(text, len, name, edit, diag) &
        bind(C, name="vi_scene_edit_create")
      import :: c_int, c_int64_t, c_ptr, c_char, vi_diag
      character(kind=c_char), intent(in) :: text(*), name(*)
      integer(c_int64_t), value :: len
      type(c_ptr) :: edit
      type(vi_diag), optional :: diag
    end function
    !> as vi_scene_edit_create, at most max_depth levels of nesting (<= 0: default)
    integer(c_int) function vi_scene_edit_create_limited(text, len, name, max_depth, &
        edit, diag) bind(C, name="vi_scene_edit_create_limited")
      import :: c_int, c_int64_t, c_ptr, c_char, vi_diag
      character(kind=c_char), intent(in) :: text(*), name(*)
      integer(c_int64_t), value :: len
      integer(c_int), value :: max_depth
      type(c_ptr) :: edit
      type(vi_diag), optional :: diag
    end function
    subroutine vi_scene_edit_destroy(edit) bind(C, name="vi_scene_edit_destroy")
      import :: c_ptr
      type(c_ptr) :: edit
    end subroutine
    integer(c_int) function vi_scene_edit_set(edit, key, val, diag) bind(C, name="vi_scene_edit_set")
      import :: c_int, c_ptr, c_char, vi_diag
      type(c_ptr), value :: edit
      character(kind=c_char), intent(in) :: key(*), val(*)
      type(vi_diag), optional :: diag
    end function
    integer(c_int) function vi_scene_edit_assign(edit, assignment, diag) &
        bind(C, name="vi_scene_edit_assign")
      import :: c_int, c_ptr, c_char, vi_diag
      type(c_ptr), value :: edit
      character(kind=c_char), intent(in) :: assignment(*)
      type(vi_diag), optional :: diag
    end function
    integer(c_int) function vi_scene_edit_set_number(edit, key, val, diag) &
        bind(C, name="vi_scene_edit_set_number")
      import :: c_int, c_ptr, c_char, c_double, vi_diag
      type(c_ptr), value :: edit
      character(kind=c_char), intent(in) :: key(*)
      real(c_double), value :: val
      type(vi_diag), optional :: diag
    end function
    integer(c_int) function vi_scene_edit_get(edit, key, buf, len, diag) bind(C, name="vi_scene_edit_get")
      import :: c_int, c_ptr, c_char, vi_diag
      type(c_ptr), value :: edit
      character(kind=c_char), intent(in) :: key(*)
      character(kind=c_char) :: buf(*)
      integer(c_int), value :: len
      type(vi_diag), optional :: diag
    end function
    type(c_ptr) function vi_scene_edit_text(edit) bind(C, name="vi_scene_edit_text")
      import :: c_ptr
      type(c_ptr), value :: edit
    end function
    integer(c_int) function vi_scene_edit_parse(edit, scene, diag) bind(C, name="vi_scene_edit_parse")
      import :: c_int, c_ptr, vi_diag
      type(c_ptr), value :: edit
      type(c_ptr) :: scene
      type(vi_diag), optional :: diag
    end function
    integer(c_int) function vi_scene_edit_parse_within(edit, max_memory, scene, diag) &
        bind(C, name="vi_scene_edit_parse_within")
      import :: c_int, c_double, c_ptr, vi_diag
      type(c_ptr), value :: edit
      real(c_double), value :: max_memory
      type(c_ptr) :: scene
      type(vi_diag), optional :: diag
    end function
    subroutine vi_scene_destroy(scene) bind(C, name="vi_scene_destroy")
      import :: c_ptr
      type(c_ptr) :: scene
    end subroutine
    integer(c_int) function vi_scene_create_model(scene, model, diag) bind(C, name="vi_scene_create_model")
      import :: c_int, c_ptr, vi_diag
      type(c_ptr), value :: scene
      type(c_ptr) :: model
      type(vi_diag), optional :: diag
    end function
    integer(c_int) function vi_scene_configure_sim(scene, sim, diag) bind(C, name="vi_scene_configure_sim")
      import :: c_int, c_ptr, vi_diag
      type(c_ptr), value :: scene, sim
      type(vi_diag), optional :: diag
    end function
    integer(c_int) function vi_scene_param_key(scene, key, out, len, diag) &
        bind(C, name="vi_scene_param_key")
      import :: c_int, c_ptr, c_char, vi_diag
      type(c_ptr), value :: scene
      character(kind=c_char), intent(in) :: key(*)
      character(kind=c_char), intent(out) :: out(*)
      integer(c_int), value :: len
      type(vi_diag), optional :: diag
    end function
    type(c_ptr) function vi_scene_name(scene) bind(C, name="vi_scene_name")
      import :: c_ptr
      type(c_ptr), value :: scene
    end function
    type(c_ptr) function vi_scene_text(scene) bind(C, name="vi_scene_text")
      import :: c_ptr
      type(c_ptr), value :: scene
    end function
    integer(c_int) function vi_scene_n(scene) bind(C, name="vi_scene_n")
      import :: c_int, c_ptr
      type(c_ptr), value :: scene
    end function
    !> x0, v0(vi_scene_dofs(scene)), each optional
    integer(c_int) function vi_scene_initial(scene, x0, v0) bind(C, name="vi_scene_initial")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: scene
      real(c_double), optional :: x0(*), v0(*)
    end function
    integer(c_int) function vi_scene_dofs(scene) bind(C, name="vi_scene_dofs")
      import :: c_int, c_ptr
      type(c_ptr), value :: scene
    end function
    integer(c_int) function vi_scene_fe_summary(scene, modes, rule, massless, rigid, &
        max_residual, orthogonality) bind(C, name="vi_scene_fe_summary")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: scene
      integer(c_int), optional :: modes, rule, massless, rigid
      real(c_double), optional :: max_residual, orthogonality
    end function
    !> modes 0: the scene's model.modes; keep 1: the full Psi; fe receives
    !> the set-up reduction (module vibroimpact's vi_fe_* routines)
    integer(c_int) function vi_scene_create_fe(scene, modes, keep, fe, diag) &
        bind(C, name="vi_scene_create_fe")
      import :: c_int, c_ptr, vi_diag
      type(c_ptr), value :: scene
      integer(c_int), value :: modes, keep
      type(c_ptr) :: fe
      type(vi_diag), optional :: diag
    end function
    real(c_double) function vi_scene_t0(scene) bind(C, name="vi_scene_t0")
      import :: c_double, c_ptr
      type(c_ptr), value :: scene
    end function
    real(c_double) function vi_scene_t_end(scene) bind(C, name="vi_scene_t_end")
      import :: c_double, c_ptr
      type(c_ptr), value :: scene
    end function
    real(c_double) function vi_scene_rtol(scene) bind(C, name="vi_scene_rtol")
      import :: c_double, c_ptr
      type(c_ptr), value :: scene
    end function
    real(c_double) function vi_scene_atol(scene) bind(C, name="vi_scene_atol")
      import :: c_double, c_ptr
      type(c_ptr), value :: scene
    end function
    integer(c_int) function vi_scene_method(scene) bind(C, name="vi_scene_method")
      import :: c_int, c_ptr
      type(c_ptr), value :: scene
    end function
    integer(c_int) function vi_scene_samples_per_period(scene) bind(C, name="vi_scene_samples_per_period")
      import :: c_int, c_ptr
      type(c_ptr), value :: scene
    end function
    !> an OR of VI_SCENE_OUT_* bits: iand(vi_scene_outputs(scene), VI_SCENE_OUT_LEDGER) /= 0
    integer(c_int) function vi_scene_outputs(scene) bind(C, name="vi_scene_outputs")
      import :: c_int, c_ptr
      type(c_ptr), value :: scene
    end function
    integer(c_int) function vi_scene_set_run(scene, rtol, atol, periods, method) &
        bind(C, name="vi_scene_set_run")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: scene
      real(c_double), value :: rtol, atol, periods
      integer(c_int), value :: method
    end function
    !> buf: character(kind=c_char) :: buf(len), then vi_chars(buf)
    subroutine vi_diag_format(diag, buf, len) bind(C, name="vi_diag_format")
      import :: c_int, c_char, vi_diag
      type(vi_diag), intent(in) :: diag
      character(kind=c_char) :: buf(*)
      integer(c_int), value :: len
    end subroutine
    type(c_ptr) function vi_scene_default_text() bind(C, name="vi_scene_default_text")
      import :: c_ptr
    end function

    ! ---- HDF5 writer (libvibroimpact_h5) ----------------------------------------
    !> path: C string; scene of vi_writer_write_header may be c_null_ptr
    integer(c_int) function vi_writer_create(path, model, compress, writer, diag) &
        bind(C, name="vi_writer_create")
      import :: c_int, c_ptr, c_char, vi_diag
      character(kind=c_char), intent(in) :: path(*)
      type(c_ptr), value :: model
      integer(c_int), value :: compress
      type(c_ptr) :: writer
      type(vi_diag), optional :: diag
    end function
    integer(c_int) function vi_writer_write_header(writer, scene, rtol, atol, method) &
        bind(C, name="vi_writer_write_header")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: writer, scene
      real(c_double), value :: rtol, atol
      integer(c_int), value :: method
    end function
    integer(c_int) function vi_writer_event(writer, ev) bind(C, name="vi_writer_event")
      import :: c_int, c_ptr, vi_event
      type(c_ptr), value :: writer
      type(vi_event), intent(in) :: ev
    end function
    integer(c_int) function vi_writer_sample(writer, t, x, v) bind(C, name="vi_writer_sample")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: writer
      real(c_double), value :: t
      real(c_double), intent(in) :: x(*), v(*)
    end function
    integer(c_int) function vi_writer_ledger(writer, iv) bind(C, name="vi_writer_ledger")
      import :: c_int, c_ptr, vi_ledger_interval
      type(c_ptr), value :: writer
      type(vi_ledger_interval), intent(in) :: iv
    end function
    integer(c_int) function vi_writer_orbit(writer, orbit) bind(C, name="vi_writer_orbit")
      import :: c_int, c_ptr
      type(c_ptr), value :: writer, orbit
    end function
    !> what: 'impacts'//c_null_char, 'trajectory' or 'ledger'
    integer(c_int64_t) function vi_writer_rows(writer, what) bind(C, name="vi_writer_rows")
      import :: c_int64_t, c_ptr, c_char
      type(c_ptr), value :: writer
      character(kind=c_char), intent(in) :: what(*)
    end function
    !> path, target: character strings ending in c_null_char; target has len
    integer(c_int) function vi_output_resolve(path, target, len, diag) bind(C, name="vi_output_resolve")
      import :: c_int, c_char, vi_diag
      character(kind=c_char), intent(in) :: path(*)
      character(kind=c_char) :: target(*)
      integer(c_int), value :: len
      type(vi_diag), optional :: diag
    end function
    !> flags: VI_OUTPUT_REGULAR or VI_OUTPUT_STREAM; scene: optional path
    integer(c_int) function vi_output_check(path, flags, scene, target, len, kind, diag) &
        bind(C, name="vi_output_check")
      import :: c_int, c_char, vi_diag
      character(kind=c_char), intent(in) :: path(*)
      integer(c_int), value :: flags
      character(kind=c_char), intent(in), optional :: scene(*)
      character(kind=c_char) :: target(*)
      integer(c_int), value :: len
      integer(c_int), optional :: kind
      type(vi_diag), optional :: diag
    end function
    integer(c_int) function vi_output_part(target, part, len) bind(C, name="vi_output_part")
      import :: c_int, c_char
      character(kind=c_char), intent(in) :: target(*)
      character(kind=c_char) :: part(*)
      integer(c_int), value :: len
    end function
    integer(c_int) function vi_output_same(a, b) bind(C, name="vi_output_same")
      import :: c_int, c_char
      character(kind=c_char), intent(in) :: a(*), b(*)
    end function
    !> f: a C FILE * (type(c_ptr)), for C I/O from Fortran
    integer(c_int) function vi_output_open(target, kind, f, diag) bind(C, name="vi_output_open")
      import :: c_int, c_char, c_ptr, vi_diag
      character(kind=c_char), intent(in) :: target(*)
      integer(c_int), value :: kind
      type(c_ptr) :: f
      type(vi_diag), optional :: diag
    end function
    integer(c_int) function vi_output_close(f, target, kind, diag) bind(C, name="vi_output_close")
      import :: c_int, c_char, c_ptr, vi_diag
      type(c_ptr) :: f
      character(kind=c_char), intent(in) :: target(*)
      integer(c_int), value :: kind
      type(vi_diag), optional :: diag
    end function
    subroutine vi_output_discard(f, target, kind) bind(C, name="vi_output_discard")
      import :: c_int, c_char, c_ptr
      type(c_ptr) :: f
      character(kind=c_char), intent(in) :: target(*)
      integer(c_int), value :: kind
    end subroutine
    integer(c_int) function vi_output_commit(target, diag) bind(C, name="vi_output_commit")
      import :: c_int, c_char, vi_diag
      character(kind=c_char), intent(in) :: target(*)
      type(vi_diag), optional :: diag
    end function
    integer(c_int) function vi_writer_run_info(writer, sim) bind(C, name="vi_writer_run_info")
      import :: c_int, c_ptr
      type(c_ptr), value :: writer, sim
    end function
    integer(c_int) function vi_writer_finish(writer, complete) bind(C, name="vi_writer_finish")
      import :: c_int, c_ptr
      type(c_ptr), value :: writer
      integer(c_int), value :: complete
    end function
    integer(c_int) function vi_writer_close(writer, complete) bind(C, name="vi_writer_close")
      import :: c_int, c_ptr
      type(c_ptr) :: writer
      integer(c_int), value :: complete
    end function
    subroutine vi_writer_abort(writer) bind(C, name="vi_writer_abort")
      import :: c_ptr
      type(c_ptr) :: writer
    end subroutine
    !> t, x [ns]; path, keys NUL-terminated (keys optional)
    integer(c_int) function vi_identify_write_h5(path, id, keys, ns, t, x, diag) &
        bind(C, name="vi_identify_write_h5")
      import :: c_int, c_ptr, c_char, c_double, vi_diag
      character(kind=c_char), intent(in) :: path(*)
      type(c_ptr), value :: id
      character(kind=c_char), intent(in), optional :: keys(*)
      integer(c_int), value :: ns
      real(c_double), intent(in) :: t(*), x(*)
      type(vi_diag), optional :: diag
    end function
    !> info(VI_TRUNCATION_INFO), reference(VI_TRUNCATION_COLUMNS),
    !> rows(ldrows, VI_TRUNCATION_COLUMNS); strings NUL-terminated (names optional)
    integer(c_int) function vi_truncation_write_h5(path, scene_name, scene_text, &
        info, reference, nrows, rows, ldrows, diag) bind(C, name="vi_truncation_write_h5")
      import :: c_int, c_char, c_double, vi_diag
      character(kind=c_char), intent(in) :: path(*)
      character(kind=c_char), intent(in), optional :: scene_name(*), scene_text(*)
      real(c_double), intent(in) :: info(*), reference(*)
      integer(c_int), value :: nrows
      real(c_double), intent(in) :: rows(*)
      integer(c_int), value :: ldrows
      type(vi_diag), optional :: diag
    end function
    type(c_ptr) function vi_writer_errmsg(writer) bind(C, name="vi_writer_errmsg")
      import :: c_ptr
      type(c_ptr), value :: writer
    end function
    !> fe: a set-up vi_fe that kept its shapes (module vibroimpact)
    integer(c_int) function vi_writer_fe_shapes(writer, fe) bind(C, name="vi_writer_fe_shapes")
      import :: c_int, c_ptr
      type(c_ptr), value :: writer, fe
    end function
    ! ---- Matrix Market files (vi_mmio.h) ------------------------------------
    !> path: 'K.mtx'//c_null_char; rows, cols, entries, symmetric optional
    integer(c_int) function vi_mm_read_header(path, rows, cols, entries, symmetric, diag) &
        bind(C, name="vi_mm_read_header")
      import :: c_int, c_int64_t, c_char, vi_diag
      character(kind=c_char), intent(in) :: path(*)
      integer(c_int), optional :: rows, cols, symmetric
      integer(c_int64_t), optional :: entries
      type(vi_diag), optional :: diag
    end function
    !> storage: VI_CSC_LOWER or VI_CSC_FULL; mm receives the handle
    integer(c_int) function vi_mm_load(path, storage, mm, diag) bind(C, name="vi_mm_load")
      import :: c_int, c_ptr, c_char, vi_diag
      character(kind=c_char), intent(in) :: path(*)
      integer(c_int), value :: storage
      type(c_ptr) :: mm
      type(vi_diag), optional :: diag
    end function
    !> max_bytes <= 0: no limit
    integer(c_int) function vi_mm_load_limited(path, storage, max_bytes, mm, diag) &
        bind(C, name="vi_mm_load_limited")
      import :: c_int, c_double, c_ptr, c_char, vi_diag
      character(kind=c_char), intent(in) :: path(*)
      integer(c_int), value :: storage
      real(c_double), value :: max_bytes
      type(c_ptr) :: mm
      type(vi_diag), optional :: diag
    end function
    subroutine vi_mm_destroy(mm) bind(C, name="vi_mm_destroy")
      import :: c_ptr
      type(c_ptr) :: mm
    end subroutine
    integer(c_int) function vi_mm_rows(mm) bind(C, name="vi_mm_rows")
      import :: c_int, c_ptr
      type(c_ptr), value :: mm
    end function
    integer(c_int) function vi_mm_cols(mm) bind(C, name="vi_mm_cols")
      import :: c_int, c_ptr
      type(c_ptr), value :: mm
    end function
    integer(c_int) function vi_mm_nnz(mm) bind(C, name="vi_mm_nnz")
      import :: c_int, c_ptr
      type(c_ptr), value :: mm
    end function
    integer(c_int) function vi_mm_storage_kind(mm) bind(C, name="vi_mm_storage_kind")
      import :: c_int, c_ptr
      type(c_ptr), value :: mm
    end function
    !> views: c_f_pointer(vi_mm_colptr(mm), p, [vi_mm_cols(mm) + 1]); 0-based
    !> indices (add 1 for Fortran's)
    type(c_ptr) function vi_mm_colptr(mm) bind(C, name="vi_mm_colptr")
      import :: c_ptr
      type(c_ptr), value :: mm
    end function
    type(c_ptr) function vi_mm_rowind(mm) bind(C, name="vi_mm_rowind")
      import :: c_ptr
      type(c_ptr), value :: mm
    end function
    type(c_ptr) function vi_mm_values(mm) bind(C, name="vi_mm_values")
      import :: c_ptr
      type(c_ptr), value :: mm
    end function
    ! ---- other formats: Harwell-Boeing, coordinate (vi_mmio.h) -------------
    !> format receives VI_MATRIX_MARKET, VI_MATRIX_HARWELL_BOEING or
    !> VI_MATRIX_COORDINATE
    integer(c_int) function vi_matrix_detect(path, format, diag) &
        bind(C, name="vi_matrix_detect")
      import :: c_int, c_char, vi_diag
      character(kind=c_char), intent(in) :: path(*)
      integer(c_int) :: format
      type(vi_diag), optional :: diag
    end function
    !> format: VI_MATRIX_AUTO or one of them; rows ... symmetric optional
    integer(c_int) function vi_matrix_read_header(path, format, rows, cols, entries, &
        symmetric, diag) bind(C, name="vi_matrix_read_header")
      import :: c_int, c_int64_t, c_char, vi_diag
      character(kind=c_char), intent(in) :: path(*)
      integer(c_int), value :: format
      integer(c_int), optional :: rows, cols, symmetric
      integer(c_int64_t), optional :: entries
      type(vi_diag), optional :: diag
    end function
    !> map: c_null_ptr or a vi_dofmap_scan map (coordinate files)
    integer(c_int) function vi_matrix_load(path, format, map, storage, max_bytes, mm, &
        diag) bind(C, name="vi_matrix_load")
      import :: c_int, c_double, c_ptr, c_char, vi_diag
      character(kind=c_char), intent(in) :: path(*)
      integer(c_int), value :: format, storage
      type(c_ptr), value :: map
      real(c_double), value :: max_bytes
      type(c_ptr) :: mm
      type(vi_diag), optional :: diag
    end function
    !> paths: c_loc of each file name (NUL-terminated), nfiles of them
    integer(c_int) function vi_dofmap_scan(nfiles, paths, max_bytes, map, diag) &
        bind(C, name="vi_dofmap_scan")
      import :: c_int, c_double, c_ptr, vi_diag
      integer(c_int), value :: nfiles
      type(c_ptr) :: paths(*)
      real(c_double), value :: max_bytes
      type(c_ptr) :: map
      type(vi_diag), optional :: diag
    end function
    subroutine vi_dofmap_destroy(map) bind(C, name="vi_dofmap_destroy")
      import :: c_ptr
      type(c_ptr) :: map
    end subroutine
    integer(c_int) function vi_dofmap_n(map) bind(C, name="vi_dofmap_n")
      import :: c_int, c_ptr
      type(c_ptr), value :: map
    end function
    !> index 1-based; node and dof receive the pair
    integer(c_int) function vi_dofmap_label(map, index, node, dof) &
        bind(C, name="vi_dofmap_label")
      import :: c_int, c_ptr
      type(c_ptr), value :: map
      integer(c_int), value :: index
      integer(c_int) :: node, dof
    end function
    !> the 1-based global dof of (node, dof), 0 if absent
    integer(c_int) function vi_dofmap_index(map, node, dof) bind(C, name="vi_dofmap_index")
      import :: c_int, c_ptr
      type(c_ptr), value :: map
      integer(c_int), value :: node, dof
    end function
    !> a view owned by the scene; c_null_ptr unless coordinate files
    type(c_ptr) function vi_scene_dofmap(scene) bind(C, name="vi_scene_dofmap")
      import :: c_ptr
      type(c_ptr), value :: scene
    end function
    !> which: 0 M, 1 K, 2 C; -1 without that file
    integer(c_int) function vi_scene_matrix_format(scene, which) &
        bind(C, name="vi_scene_matrix_format")
      import :: c_int, c_ptr
      type(c_ptr), value :: scene
      integer(c_int), value :: which
    end function
  end interface

contains

  !> A NUL-terminated character array (a vi_diag field) as a Fortran string.
  function vi_chars(chars) result(s)
    character(kind=c_char), intent(in) :: chars(:)
    character(len=:), allocatable :: s
    integer :: n
    n = 0
    do while (n < size(chars))
      if (chars(n + 1) == c_null_char) exit
      n = n + 1
    end do
    allocate(character(len=n) :: s)
    s = transfer(chars(1:n), s)
  end function
end module vibroimpact_io
