!> Case reader, the values: valid 2D and 3D cases resolve every value and default (domain,
!> faces, materials, bodies, time, output, checkpoint and guard), the summary says them, and
!> body particle counts agree with a brute-force count of the placement rule. The messages
!> for bad values are tested in test_mpm_case_errors.
program test_mpm_case
    use mpm_kinds, only: wp
    use mpm_error, only: error_type, exit_input
    use mpm_case, only: case_type, read_case_file, read_case_string, case_summary, &
        scheme_musl, scheme_usl, damping_none, damping_local, &
        dist_regular, dist_random
    use mpm_case_output_fields, only: field_position, output_field_index
    use mpm_case_stability, only: critical_time_step, p_wave_speed
    use mpm_case_materials, only: state_variable_count
    use mpm_case_guard, only: snapshot_in_file, snapshot_in_memory
    use mpm_boundary, only: face_nodes_type
    use mpm_softening, only: softening_none, softening_linear, softening_exponential
    use mpm_strength, only: strength_type
    use mpm_material_drucker_prager, only: cone_plane_strain, cone_compression
    use mpm_testing, only: test_suite_type, new_suite, check, check_close, check_contains, finish
    use mpm_testing_case, only: domain_2d, materials_1, materials_2, time_1, tol, degree, &
        elastic_part, case_text, soil_case, faces_case, read_valid, expect_error, write_text, &
        delete_file, young_of, poisson_of, strength_of, cone_of, fluid_of
    implicit none

    character(len=*), parameter :: state_file = "test_mpm_case_state.tmp"
        !! a file whose existence load_state checks
    character(len=*), parameter :: case_file = "test_mpm_case_tmp.json"
        !! a case written to disk for read_case_file

    type(test_suite_type) :: suite

    call new_suite(suite, "mpm_case")
    call write_text(state_file, "not a real state file: only its existence is checked")
    call test_valid_2d()
    call test_valid_3d()
    call test_manual_keys()
    call test_read_file()
    call test_particle_counts()
    call test_summary()
    call test_material_types()
    call test_material_summary()
    call test_frictional_faces()
    call test_checkpoint_and_guard()
    call check_neo_hookean_and_unstable()
    call delete_file(state_file)
    call delete_file(case_file)
    call finish(suite)

contains

    subroutine test_valid_2d()
        type(case_type) :: case

        call read_valid(suite, '{"name": "column", "domain": {"nx": 4, "ny": 2, "dx": 0.1, ' &
            //'"boundaries": {"xmin": "fixed", "xmax": "Sliding"}}, '//materials_1//", " &
            //'"bodies": [{"material": "soil", "min": [0, 0], "max": [0.2, 0.1], ' &
            //'"velocity": [1, 0]}], "gravity": [0, -9.81], ' &
            //'"solver": {"scheme": "musl", "shape_function": "GIMP", "transfer": "APIC"}, ' &
            //time_1//"}", &
            case, "valid 2D case")
        if (.not. allocated(case%bodies)) return
        call check(suite, case%dim == 2, "2D: dimension 2 without nz")
        call check(suite, .not. case%solver%fbar, "2D: no locking correction by default")
        call check(suite, case%solver%apic, "2D: APIC transfer")
        call check(suite, all(case%domain%ncells == [4, 2, 1]), "2D: ncells with nz = 1")
        call check_close(suite, case%domain%dx, 0.1_wp, tol, "2D: dx")
        call check(suite, all(case%domain%origin == 0.0_wp), "2D: origin defaults to zero")
        call check(suite, case%domain%face_text(1, 1) == "fixed" &
            .and. case%domain%face_text(2, 1) == "sliding", "2D: x boundaries (any case)")
        call check(suite, case%domain%face_text(1, 2) == "free" &
            .and. case%domain%face_text(2, 2) == "free", "2D: other faces free")
        call check(suite, case%particles%ppc == 2 .and. case%particles%distribution == dist_regular, &
            "2D: particles default to ppc 2, regular")
        call check(suite, case%materials(1)%name == "soil" .and. &
            case%materials(1)%type == "linear_elastic", "2D: material name and type")
        call check_close(suite, young_of(case%materials(1)), 1.0e6_wp, tol*1.0e6_wp, "2D: E")
        call check_close(suite, case%materials(1)%density, 1000.0_wp, tol*1000, "2D: rho")
        call check(suite, case%bodies(1)%name == "body1", "2D: default body name")
        call check(suite, case%bodies(1)%material == 1, "2D: body material index")
        call check_close(suite, case%bodies(1)%xmax(1), 0.2_wp, tol, "2D: body max x")
        call check_close(suite, case%bodies(1)%velocity(1), 1.0_wp, tol, "2D: body velocity")
        call check_close(suite, case%gravity(2), -9.81_wp, tol*10, "2D: gravity y")
        call check(suite, case%solver%scheme == scheme_musl, "2D: scheme 'musl' is MUSL")
        call check(suite, case%solver%shape_function == "gimp", "2D: 'GIMP' kept in lower case")
        call check_close(suite, case%time%tend, 0.1_wp, tol, "2D: tend")
        call check(suite, case%time%dt == 0.0_wp, "2D: no fixed dt")
        call check_close(suite, case%time%cfl, 0.5_wp, 0.0_wp, "2D: cfl defaults to 0.5")
        call check(suite, case%damping%type == damping_none, "2D: no damping by default")
        call check_close(suite, case%output%interval, 0.1_wp/20, tol, "2D: interval tend/20")
        call check_close(suite, case%output%history_interval, 0.1_wp/200, tol, &
            "2D: history interval is interval/10")
        call check(suite, case%output%directory == "outputs/column", "2D: output folder")
        call check(suite, all(case%output%fields), "2D: all fields by default")
        call check(suite, .not. case%output%grid .and. .not. case%output%overwrite, &
            "2D: no grid output, no overwrite")
        call check(suite, case%save_state == "" .and. case%load_state == "", "2D: no states")
        call check(suite, case%contact%type == "none", "2D: contact none")
        call check(suite, case%file == "<string>", "2D: file of a string case")
        call check_close(suite, case%progress%interval, 2.0_wp, 0.0_wp, "2D: progress 2 s")
        call check_close(suite, critical_time_step(case%dim, case%domain%dx, case%materials, &
            case%bodies), 0.1_wp/(sqrt(1.0e3_wp) + 1), 1.0e-12_wp, &
            "2D: critical step dx/(c_p + |v|)")
        call read_valid(suite, case_text(), case, "default pieces")
        call check(suite, case%name == "case", "name of a case without source is 'case'")
    end subroutine test_valid_2d

    subroutine test_valid_3d()
        type(case_type) :: case

        call read_valid(suite, '{"name": "cube-3d.v1", "domain": {"nx": 2, "ny": 3, "nz": 4, ' &
            //'"dx": 0.5, "origin": [1, 2, 3], "boundaries": {"zmin": "fixed"}}, ' &
            //'"particles": {"ppc": 3, "distribution": "random", "seed": 7}, ' &
            //materials_2//', "bodies": [{"name": "b", "material": "rock", ' &
            //'"min": [1, 2, 3], "max": [2, 3.5, 5]}], "gravity": [0, 0, -9.81], ' &
            //'"solver": {"scheme": "USL", "shape_function": "linear", ' &
            //'"locking_correction": "FBar"}, ' &
            //'"time": {"tend": 1, "dt": 1e-5}, "damping": {"type": "local", "value": 0.05}, ' &
            //'"output": {"interval": 0, "fields": ["velocity", "stress"], "grid": true, ' &
            //'"directory": "out/cube", "overwrite": true}, "progress": {"interval": 0.5}, ' &
            //'"save_state": "out/cube/state.h5"}', case, "valid 3D case")
        if (.not. allocated(case%bodies)) return
        call check(suite, case%dim == 3, "3D: dimension 3 from nz")
        call check(suite, all(case%domain%ncells == [2, 3, 4]), "3D: ncells")
        call check(suite, all(abs(case%domain%origin - [1, 2, 3]) <= tol*3), "3D: origin")
        call check(suite, case%domain%face_text(1, 3) == "fixed" &
            .and. case%domain%face_text(2, 3) == "free", "3D: z faces")
        call check(suite, case%particles%ppc == 3 .and. case%particles%distribution == dist_random .and. &
            case%particles%seed == 7, "3D: random particles with seed")
        call check(suite, case%materials(2)%type == "linear_elastic", &
            "3D: 'elastic' resolves to linear_elastic")
        call check_close(suite, poisson_of(case%materials(2)), 0.25_wp, tol, "3D: nu")
        call check(suite, case%bodies(1)%material == 2, "3D: body uses material 2")
        call check(suite, case%solver%scheme == scheme_usl .and. case%solver%shape_function == "linear", &
            "3D: scheme and shape")
        call check(suite, case%solver%fbar, "3D: F-bar locking correction")
        call check(suite, .not. case%solver%apic .and. case%solver%flip_fraction == 1.0_wp, &
            "3D: FLIP transfer by default")
        call check_close(suite, case%time%dt, 1.0e-5_wp, tol*1.0e-5_wp, "3D: fixed dt")
        call check(suite, case%damping%type == damping_local, "3D: local damping")
        call check_close(suite, case%damping%value, 0.05_wp, tol, "3D: damping alpha")
        call check(suite, case%output%interval == 0.0_wp .and. case%output%history_interval == 0.0_wp, &
            "3D: interval 0 gives history interval 0")
        call check(suite, case%output%fields(field_position) .and. &
            case%output%fields(output_field_index("velocity")) .and. &
            case%output%fields(output_field_index("stress")) .and. &
            count(case%output%fields) == 3, "3D: listed fields plus position")
        call check(suite, case%output%grid .and. case%output%overwrite, "3D: grid and overwrite")
        call check(suite, case%output%directory == "out/cube", "3D: output directory")
        call check_close(suite, case%progress%interval, 0.5_wp, 0.0_wp, "3D: progress")
        call check(suite, case%save_state == "out/cube/state.h5", "3D: save_state")
        call check(suite, case%name == "cube-3d.v1", "3D: name with '-' and '.'")
    end subroutine test_valid_3d

    !> Every key of the user manual is known: domain.nx/ny/nz/dx, particles.ppc/distribution,
    !> materials[].name/type/E/nu/rho, contact.type/mu/file, time.dt/tend,
    !> damping.type/value, save_state, load_state.
    subroutine test_manual_keys()
        type(case_type) :: case
        type(error_type), allocatable :: error

        call read_valid(suite, '{"dimension": 3, "domain": {"nx": 2, "ny": 2, "nz": 2, "dx": 1}, ' &
            //'"particles": {"ppc": 2, "distribution": "regular"}, '//materials_1//", " &
            //'"contact": {"type": "none"}, "time": {"tend": 1, "dt": 1e-3}, ' &
            //'"damping": {"type": "local", "value": 0.1}, "save_state": "s.h5", ' &
            //'"load_state": "'//state_file//'"}', case, "all manual keys")
        call check(suite, case%load_state == state_file, "load_state kept")
        if (allocated(case%bodies)) then
            call check(suite, size(case%bodies) == 0, "no bodies with load_state")
        end if
        ! contact.mu and contact.file are known keys, refused only because type is "none"
        call read_case_string(case_text(extra='"contact": {"type": "none", "mu": 0.4}'), case, &
            error)
        call check(suite, allocated(error), "contact.mu with type none is refused")
        if (allocated(error)) then
            call check(suite, index(error%message, "unknown key") == 0, "contact.mu is known")
        end if
        call read_case_string(case_text(extra='"contact": {"type": "terrain_stl", "mu": 0.4, ' &
            //'"file": "tests/data/stl/floor_2.stl", "scale": 0.001, "offset": [1, 2, 3]}'), &
            case, error)
        call check(suite, .not. allocated(error), "contact terrain_stl with scale and offset")
        if (.not. allocated(error)) then
            call check(suite, case%contact%type == "terrain_stl" .and. case%contact%mu == 0.4_wp &
                .and. case%contact%file == "tests/data/stl/floor_2.stl" .and. &
                case%contact%scale == 0.001_wp .and. all(case%contact%offset == [1, 2, 3]), &
                "contact: type, mu, file, scale and offset read")
        end if
        call read_case_string(case_text(extra='"contact": {"file": "t.stl"}'), case, error)
        if (allocated(error)) then
            call check_contains(suite, error%message, "contact.file only applies to " &
                //'contact.type = "terrain_stl"', "contact.file is known")
        end if
    end subroutine test_manual_keys

    subroutine test_read_file()
        type(case_type) :: case
        type(error_type), allocatable :: error

        call write_text(case_file, case_text())
        call read_case_file(case_file, case, error)
        call check(suite, .not. allocated(error), "read_case_file of a valid file")
        if (allocated(error)) return
        call check(suite, case%name == "test_mpm_case_tmp", "default name from the file name")
        call check(suite, case%file == case_file, "case%file is the path")
        call check(suite, case%output%directory == "outputs/test_mpm_case_tmp", "default output dir")

        call write_text(case_file, case_text(domain='"domain": {"nx": 4, "ny": 2, "dx": -1}'))
        call read_case_file(case_file, case, error)
        call check(suite, allocated(error), "read_case_file reports errors")
        if (allocated(error)) then
            call check_contains(suite, error%message, case_file//": domain.dx = -1", &
                "file error starts with the file name")
        end if
        call read_case_file("no_such_dir/no_such_case.json", case, error)
        call check(suite, allocated(error), "missing case file")
        if (allocated(error)) then
            call check(suite, error%code == exit_input, "missing case file: exit_input")
            call check_contains(suite, error%message, "not found", "missing case file message")
        end if
    end subroutine test_read_file

    !> The count in the summary is compared with a brute-force count of the placement rule:
    !> particle k of cell i sits at origin + (i + (k - 0.5)/ppc) dx; the body holds it when it
    !> is in [min, max) along every axis.
    subroutine test_particle_counts()
        character(len=*), parameter :: boxes(4) = [character(len=200) :: &
            '"min": [0, 0], "max": [0.2, 0.1]', '"min": [0, 0], "max": [0.125, 0.1]', &
            '"min": [0.025, 0.05], "max": [0.3, 0.2]', '"min": [0.07, 0.0], "max": [0.4, 0.08]']
        real(wp), parameter :: lower(2, 4) = reshape([0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, &
            0.025_wp, 0.05_wp, 0.07_wp, 0.0_wp], [2, 4])
        real(wp), parameter :: upper(2, 4) = reshape([0.2_wp, 0.1_wp, 0.125_wp, 0.1_wp, &
            0.3_wp, 0.2_wp, 0.4_wp, 0.08_wp], [2, 4])
        type(case_type) :: case
        integer :: b, d, i, k, n, axis_count(2)
        character(len=20) :: buf
        real(wp) :: x

        do b = 1, size(boxes)
            call read_valid(suite, case_text(bodies='"bodies": [{"name": "box", "material": "soil", ' &
                //trim(boxes(b))//"}]"), case, "count box "//trim(boxes(b)))
            if (.not. allocated(case%bodies)) cycle
            do d = 1, 2
                axis_count(d) = 0
                do i = 0, case%domain%ncells(d) - 1
                    do k = 1, case%particles%ppc
                        x = (i + (k - 0.5_wp)/case%particles%ppc)*case%domain%dx
                        if (x >= lower(d, b) .and. x < upper(d, b)) then
                            axis_count(d) = axis_count(d) + 1
                        end if
                    end do
                end do
            end do
            n = product(axis_count)
            write (buf, "(i0)") n
            call check_contains(suite, case_summary(case), "m/s, "//trim(buf)//" particles", &
                "particle count of box "//trim(boxes(b)))
        end do
    end subroutine test_particle_counts

    subroutine test_summary()
        type(case_type) :: case
        character(len=:), allocatable :: text

        call read_valid(suite, case_text(extra='"damping": {"type": "local", "value": 0.05}'), case, &
            "summary case")
        text = case_summary(case)
        call check_contains(suite, text, "dimension   2", "summary: dimension")
        call check_contains(suite, text, "4 x 2 cells, 5 x 3 = 15 nodes, dx = 0.1 m", &
            "summary: grid")
        call check_contains(suite, text, "[0, 0.4] x [0, 0.2] m", "summary: extent")
        call check_contains(suite, text, "xmin free", "summary: boundaries")
        call check_contains(suite, text, '"soil" linear_elastic: E = 1000000 Pa, nu = 0, ' &
            //"rho = 1000 kg/m3, c_p = 31.6228 m/s", "summary: material")
        call check_contains(suite, text, '"block" material "soil": [0, 0.2] x [0, 0.1] m', &
            "summary: body box")
        call check_contains(suite, text, "8 particles", "summary: particles")
        call check_contains(suite, text, "scheme MUSL, shape function cpgimp", "summary: solver")
        call check_contains(suite, text, "critical time step 0.00316228 s", "summary: dt crit")
        call check_contains(suite, text, "local, alpha = 0.05", "summary: damping")
        call check_contains(suite, text, "outputs/case, every 0.005 s", "summary: output")
        call check_contains(suite, text, "position displacement velocity", "summary: fields")
        call check_contains(suite, text, "load_state  (none)", "summary: load_state")
        call check_contains(suite, text, "checkpoint  on SIGTERM/SIGINT, file <output folder>/" &
            //"checkpoint.h5", "summary: checkpoints by default")
        call check_contains(suite, text, "guard       energy created above 1 x the energy " &
            //"scale; healthy copy every 100 steps", "summary: guard by default")
    end subroutine test_summary

    !> `checkpoint` and `guard`: values, defaults, ranges, misspelt keys; the text of the case
    !> is kept (checkpoints store it).
    subroutine test_checkpoint_and_guard()
        type(case_type) :: case
        character(len=:), allocatable :: text

        text = case_text(extra='"checkpoint": {"every_steps": 250, "every_minutes": 30, ' &
            //'"file": "ck/run.h5", "on_signal": false}, "guard": {"energy_factor": 50, ' &
            //'"snapshot_steps": 0}')
        call read_valid(suite, text, case, "checkpoint and guard")
        call check(suite, case%checkpoint%every_steps == 250, "checkpoint.every_steps")
        call check_close(suite, case%checkpoint%every_minutes, 30.0_wp, 0.0_wp, &
            "checkpoint.every_minutes")
        call check(suite, case%checkpoint%file == "ck/run.h5", "checkpoint.file")
        call check(suite, .not. case%checkpoint%on_signal, "checkpoint.on_signal")
        call check_close(suite, case%guard%energy_factor, 50.0_wp, 0.0_wp, "guard.energy_factor")
        call check(suite, case%guard%snapshot_steps == 0, "guard.snapshot_steps")
        call check(suite, case%text == text, "the case text is kept")
        call check_contains(suite, case_summary(case), "checkpoint  every 250 steps, every " &
            //"30 min, not on signals, file ck/run.h5", "summary: checkpoint")
        call check_contains(suite, case_summary(case), "no healthy copy", "summary: no copy")
        call read_valid(suite, case_text(), case, "defaults")
        call check(suite, case%checkpoint%every_steps == 0 .and. case%checkpoint%every_minutes == 0.0_wp &
            .and. case%checkpoint%on_signal .and. case%checkpoint%file == "", &
            "checkpoint defaults: none periodic, on signals, default file")
        call check(suite, case%guard%energy_factor == 1.0_wp .and. &
            case%guard%snapshot_steps == 100 .and. case%guard%snapshot_in == snapshot_in_file, &
            "guard defaults")
        call check_contains(suite, case_summary(case), "healthy copy every 100 steps, in " &
            //"<output folder>/.last_healthy.h5", "summary: copy in a file")
        call read_valid(suite, case_text(extra='"guard": {"snapshot_in": "Memory"}'), case, &
            "copy in memory")
        call check(suite, case%guard%snapshot_in == snapshot_in_memory, "guard.snapshot_in")
        call check_contains(suite, case_summary(case), "healthy copy every 100 steps, in memory", &
            "summary: copy in memory")
        call expect_error(suite, case_text(extra='"checkpoint": {"every_steps": 0}'), &
            [character(len=40) :: "checkpoint.every_steps", ">= 1"], "every_steps 0")
        call expect_error(suite, case_text(extra='"checkpoint": {"every_minutes": -1}'), &
            [character(len=40) :: "checkpoint.every_minutes", "> 0"], "every_minutes < 0")
        call expect_error(suite, case_text(extra='"checkpoint": {"every_step": 10}'), &
            [character(len=40) :: "every_step", "did you mean 'every_steps'"], "misspelt key")
        call expect_error(suite, case_text(extra='"checkpoint": {"on_signal": "yes"}'), &
            [character(len=40) :: "checkpoint.on_signal"], "on_signal not a boolean")
        call expect_error(suite, case_text(extra='"guard": {"energy_factor": 0}'), &
            [character(len=40) :: "guard.energy_factor", "> 0"], "energy_factor 0")
        call expect_error(suite, case_text(extra='"guard": {"snapshot_steps": -5}'), &
            [character(len=40) :: "guard.snapshot_steps", ">= 0"], "snapshot_steps < 0")
        call expect_error(suite, case_text(extra='"guard": {"snapshot_in": "disk"}'), &
            [character(len=40) :: "guard.snapshot_in", "one of", '"file"', '"memory"'], &
            "snapshot_in not a place")
    end subroutine test_checkpoint_and_guard

    !> Each material type resolves with its values; angles are stored in radians.
    subroutine test_material_types()
        type(case_type) :: case
        type(strength_type) :: str

        call read_valid(suite, soil_case('"type": "mohr_coulomb", '//elastic_part//', "phi": 30, ' &
            //'"c": 1000, "psi": 5, "tension_cutoff": 500, "softening": {"type": "linear", ' &
            //'"phi_residual": 25, "c_residual": 100, "strain": 0.1}'), case, "Mohr-Coulomb")
        if (allocated(case%materials)) then
            str = strength_of(case%materials(1))
            associate (mat => case%materials(1))
                call check(suite, mat%type == "mohr_coulomb", "MC: type")
                call check_close(suite, young_of(mat), 1.0e7_wp, tol*1.0e7_wp, "MC: E")
                call check_close(suite, str%friction, 30*degree, tol, "MC: phi 30 deg in rad")
                call check_close(suite, str%cohesion, 1000.0_wp, tol*1000, "MC: c")
                call check_close(suite, str%dilatancy, 5*degree, tol, "MC: psi 5 deg in rad")
                call check_close(suite, str%tension_cutoff, 500.0_wp, tol*500, "MC: cutoff")
                call check(suite, str%softening == softening_linear, "MC: linear softening")
                call check_close(suite, str%friction_residual, 25*degree, tol, &
                    "MC: residual phi in rad")
                call check_close(suite, str%cohesion_residual, 100.0_wp, tol*100, "MC: c_r")
                call check(suite, str%dilatancy_residual == 0.0_wp, &
                    "MC: psi_residual defaults to 0")
                call check_close(suite, str%softening_strain, 0.1_wp, tol, "MC: strain")
            end associate
        end if
        call read_valid(suite, soil_case('"type": "mohr_coulomb", '//elastic_part//', "phi": 30'), &
            case, "Mohr-Coulomb defaults")
        call check(suite, state_variable_count(case%materials) == 2, "MC: 2 state variables")
        if (allocated(case%materials)) then
            str = strength_of(case%materials(1))
            associate (mat => case%materials(1))
                call check(suite, str%cohesion == 0.0_wp .and. str%dilatancy == 0.0_wp, &
                    "MC: c and psi default to 0")
                call check(suite, str%tension_cutoff < 0.0_wp, "MC: no tension cutoff given")
                call check(suite, str%softening == softening_none, "MC: no softening")
                call check(suite, str%friction_residual == str%friction .and. &
                    str%cohesion_residual == str%cohesion .and. &
                    str%dilatancy_residual == str%dilatancy, &
                    "MC: residual = peak without softening")
            end associate
        end if
        ! phi = 0 (Tresca): no apex, any tension cutoff >= 0 is accepted
        call read_valid(suite, soil_case('"type": "Mohr_Coulomb", '//elastic_part//', "phi": 0, ' &
            //'"c": 1000, "tension_cutoff": 5000'), case, "Tresca with a tension cutoff")
        call read_valid(suite, soil_case('"type": "mohr_coulomb", '//elastic_part//', "phi": 30, ' &
            //'"c": 0, "tension_cutoff": 0, "softening": {"type": "none"}'), case, &
            "cohesionless soil with zero tension cutoff at the apex")
        str = strength_of(case%materials(1))
        call check(suite, .not. str%separation, "MC: no separation by default")
        call read_valid(suite, soil_case('"type": "mohr_coulomb", '//elastic_part//', "phi": 30, ' &
            //'"c": 2000, "tension_cutoff": 0, "separation": true'), case, &
            "separation with c > 0 and a zero tension cutoff")
        ! the particles' state rows (and the memory estimate): plastic strain, the
        ! softening's, and the separation's opening
        call check(suite, state_variable_count(case%materials) == 3, &
            "MC with separation: 3 state variables")
        call read_valid(suite, soil_case('"type": "drucker_prager", '//elastic_part//', "phi": 30, ' &
            //'"separation": true'), case, "cohesionless Drucker-Prager with separation")
        if (allocated(case%materials)) then
            str = strength_of(case%materials(1))
            call check(suite, str%separation, "DP: separation read")
            call check_contains(suite, case_summary(case), "cone plane_strain, separation", &
                "summary: separation")
        end if
        call read_valid(suite, soil_case('"type": "Drucker_Prager", '//elastic_part//', "phi": 20, ' &
            //'"c": 5000, "psi": 20, "cone": "Compression", "softening": {"type": ' &
            //'"exponential", "c_residual": 500, "psi_residual": 10, "strain": 0.05}'), case, &
            "Drucker-Prager")
        if (allocated(case%materials)) then
            str = strength_of(case%materials(1))
            associate (mat => case%materials(1))
                call check(suite, mat%type == "drucker_prager", "DP: type (any case)")
                call check(suite, cone_of(mat) == cone_compression, "DP: compression cone")
                call check_close(suite, str%friction, 20*degree, tol, "DP: phi in rad")
                call check_close(suite, str%dilatancy, 20*degree, tol, "DP: psi = phi allowed")
                call check(suite, str%softening == softening_exponential, "DP: exponential")
                call check(suite, str%friction_residual == str%friction, &
                    "DP: phi_residual defaults to the peak phi")
                call check_close(suite, str%cohesion_residual, 500.0_wp, tol*500, "DP: c_r")
                call check_close(suite, str%dilatancy_residual, 10*degree, tol, "DP: psi_r")
                call check_close(suite, str%softening_strain, 0.05_wp, tol, "DP: strain scale")
            end associate
        end if
        call read_valid(suite, soil_case('"type": "drucker_prager", '//elastic_part//', "phi": 20'), &
            case, "Drucker-Prager defaults")
        if (allocated(case%materials)) then
            call check(suite, cone_of(case%materials(1)) == cone_plane_strain, &
                "DP: plane strain cone by default")
        end if
        call read_valid(suite, soil_case('"type": "newtonian", "rho": 1000, "viscosity": 1e-3, ' &
            //'"bulk_modulus": 2.2e9'), case, "Newtonian fluid")
        if (allocated(case%materials)) then
            associate (mat => case%materials(1))
                call check(suite, mat%type == "newtonian", "fluid: type")
                call check_close(suite, fluid_of(mat, 1), 1.0e-3_wp, tol*1.0e-3_wp, "fluid: mu")
                call check_close(suite, fluid_of(mat, 2), 2.2e9_wp, tol*2.2e9_wp, "fluid: K")
                call check(suite, young_of(mat) == 0.0_wp, "fluid: no E")
                ! c_p = sqrt(K/rho) = sqrt(2.2e6) m/s
                call check_close(suite, p_wave_speed(mat), sqrt(2.2e6_wp), &
                    tol*sqrt(2.2e6_wp), "fluid: c_p = sqrt(K/rho)")
            end associate
        end if
        call read_valid(suite, soil_case('"type": "newtonian", "rho": 1000, "viscosity": 0, ' &
            //'"bulk_modulus": 1e5'), case, "inviscid fluid")
        call check(suite, state_variable_count(case%materials) == 0, "fluid: no state variables")
    end subroutine test_material_types

    !> The summary shows the parameters of each type (angles in degrees) and the limit that
    !> sets the critical time step.
    subroutine test_material_summary()
        type(case_type) :: case
        character(len=:), allocatable :: text

        call read_valid(suite, soil_case('"type": "mohr_coulomb", '//elastic_part//', "phi": 30, ' &
            //'"c": 1000, "psi": 5, "tension_cutoff": 500, "softening": {"type": "linear", ' &
            //'"phi_residual": 25, "c_residual": 100, "strain": 0.1}'), case, "MC summary case")
        text = case_summary(case)
        call check_contains(suite, text, '"soil" mohr_coulomb: E = 1e7 Pa, nu = 0.3, ' &
            //"rho = 1800 kg/m3", "summary: MC elasticity")
        call check_contains(suite, text, "phi = 30 deg, c = 1000 Pa, psi = 5 deg, tension " &
            //"cutoff 500 Pa", "summary: MC strength in degrees")
        call check_contains(suite, text, "softening linear to phi = 25 deg, c = 100 Pa, " &
            //"psi = 0 deg at plastic shear strain 0.1", "summary: MC softening")
        call read_valid(suite, soil_case('"type": "drucker_prager", '//elastic_part//', "phi": 20, ' &
            //'"c": 5000, "cone": "extension"'), case, "DP summary case")
        text = case_summary(case)
        call check_contains(suite, text, "phi = 20 deg, c = 5000 Pa, psi = 0 deg, tension " &
            //"cutoff at the apex, cone extension", "summary: DP")
        call check_contains(suite, text, "no softening", "summary: DP without softening")
        ! viscous limit rho dx^2 / (2 dim mu) = 1000 * 0.01 / (4 * 1e6) = 2.5e-6 s, below
        ! dx / c_p = 0.1 / sqrt(2.2e6) = 6.7e-5 s
        call read_valid(suite, soil_case('"type": "newtonian", "rho": 1000, "viscosity": 1e6, ' &
            //'"bulk_modulus": 2.2e9'), case, "viscous fluid summary case")
        text = case_summary(case)
        call check_contains(suite, text, '"soil" newtonian: rho = 1000 kg/m3, viscosity = ' &
            //"1000000 Pa s, bulk modulus = 2.2e9 Pa, c_p = 1483.24 m/s", "summary: fluid")
        call check_contains(suite, text, "critical time step 2.5e-6 s at t = 0 (viscous " &
            //"limit)", "summary: viscous limit of the time step")
        call expect_error(suite, case_text(materials='"materials": [{"name": "soil", "type": ' &
            //'"newtonian", "rho": 1000, "viscosity": 1e6, "bulk_modulus": 2.2e9}]', &
            time='"time": {"tend": 0.1, "dt": 1e-5}'), [character(len=200) :: "time.dt = " &
            //"1e-5 s is above the critical time step 2.5e-6 s of this case (the viscous " &
            //"limit"], "dt above the viscous limit")
        ! from a state file the viscous limit of the materials applies as well
        call expect_error(suite, "{"//domain_2d//', "materials": [{"name": "soil", "type": ' &
            //'"newtonian", "rho": 1000, "viscosity": 1e6, "bulk_modulus": 2.2e9}], ' &
            //'"load_state": "'//state_file//'", "time": {"tend": 0.1, "dt": 1e-5}}', &
            [character(len=200) :: "time.dt = 1e-5 s is above the critical time step " &
            //"2.5e-6 s of this case (the viscous limit"], "viscous limit with load_state")
    end subroutine test_material_summary

    !> Frictional faces are objects with a coefficient mu >= 0; other faces take no mu.
    subroutine test_frictional_faces()
        type(case_type) :: case
        type(face_nodes_type) :: nodes

        call read_valid(suite, faces_case('{"ymin": {"type": "Frictional", "mu": 0.4}, ' &
            //'"xmin": {"type": "fixed"}, "xmax": "sliding", "ymax": {"type": "frictional", ' &
            //'"mu": 0}}'), case, "frictional faces")
        nodes = case%domain%nodes(1, 2, 2)
        call check(suite, nodes%contact, "ymin is frictional")
        call check_close(suite, nodes%mu, 0.4_wp, tol, "ymin mu")
        nodes = case%domain%nodes(2, 2, 2)
        call check(suite, nodes%contact .and. nodes%mu == 0, "mu = 0 is allowed")
        call check(suite, case%domain%face_text(1, 1) == "fixed", "object form of a fixed face")
        call check(suite, case%domain%face_text(2, 1) == "sliding", &
            "string form beside object forms")
        nodes = case%domain%nodes(1, 1, 2)
        call check(suite, .not. nodes%contact .and. nodes%held(1) .and. nodes%held(2), &
            "fixed: no contact, every component held")
        nodes = case%domain%nodes(2, 1, 2)
        call check(suite, .not. nodes%contact .and. nodes%held(1) .and. .not. nodes%held(2), &
            "sliding: no contact, the normal component held")
        call check_contains(suite, case_summary(case), "boundaries  xmin fixed, xmax sliding, " &
            //"ymin frictional (mu = 0.4), ymax frictional (mu = 0)", "summary: frictional faces")
        call expect_error(suite, faces_case('{"ymin": {"type": "frictional"}}'), &
            [character(len=200) :: "missing required key 'domain.boundaries.ymin.mu' " &
            //"(a number >= 0)"], "frictional face without mu")
        call expect_error(suite, faces_case('{"ymin": {"type": "frictional", "mu": -0.1}}'), &
            [character(len=200) :: &
            "domain.boundaries.ymin.mu = -0.1 is out of range: must be >= 0"], "mu < 0")
        call expect_error(suite, faces_case('{"ymin": {"type": "frictional", "mu": 1e999}}'), &
            [character(len=200) :: "domain.boundaries.ymin.mu is not a finite number"], &
            "mu not finite")
        call expect_error(suite, faces_case('{"ymin": {"type": "fixed", "mu": 0.4}}'), &
            [character(len=200) :: "domain.boundaries.ymin.mu applies to frictional faces " &
            //'only (here domain.boundaries.ymin.type = "fixed")'], "mu on a fixed face")
        call expect_error(suite, faces_case('{"ymin": "frictional"}'), [character(len=200) :: &
            'domain.boundaries.ymin = "frictional" needs a friction coefficient', &
            '{"type": "frictional", "mu": 0.4}'], "frictional as a string")
        call expect_error(suite, faces_case('{"ymin": {"mu": 0.4}}'), [character(len=200) :: &
            "missing required key 'domain.boundaries.ymin.type'"], "face object without type")
        call expect_error(suite, faces_case('{"ymin": {"type": "glued"}}'), [character(len=200) :: &
            'domain.boundaries.ymin.type = "glued" is not allowed: must be one of "free", ' &
            //'"sliding", "fixed", "frictional"'], "unknown face type in an object")
        call expect_error(suite, faces_case('{"ymin": {"type": "frictional", "mu": 0.4, ' &
            //'"friction": 1}}'), [character(len=200) :: "unknown key " &
            //"'domain.boundaries.ymin.friction'", "are: type, mu"], "unknown key of a face")
        call expect_error(suite, faces_case('{"ymin": 0.4}'), [character(len=200) :: &
            "domain.boundaries.ymin has the wrong type", "found a number (0.4)"], &
            "face given as a number")
    end subroutine test_frictional_faces

    !> The neo-Hookean type and the explicit override of the stability checks.
    subroutine check_neo_hookean_and_unstable()
        type(case_type) :: case

        call read_valid(suite, soil_case('"type": "neo_hookean", '//elastic_part), case, &
            "neo_hookean material")
        call check(suite, state_variable_count(case%materials) == 9, &
            "neo_hookean: 9 state variables (F - I), not 2")
        if (allocated(case%materials)) then
            call check(suite, case%materials(1)%type == "neo_hookean", "neo_hookean type kept")
            call check_close(suite, young_of(case%materials(1)), 1.0e7_wp, tol*1.0e7_wp, &
                "neo_hookean E")
        end if
        call expect_error(suite, soil_case('"type": "neo_hookean", '//elastic_part//', "phi": 30'), &
            [character(len=60) :: "unknown key 'materials[1].phi'"], "phi of a neo_hookean")
        call expect_error(suite, case_text(time='"time": {"tend": 0.1, "cfl": 2}'), &
            [character(len=60) :: "time.cfl", "2"], "cfl above 1 without override")
        call read_valid(suite, case_text(time='"time": {"tend": 0.1, "cfl": 2, "allow_unstable": true}'), &
            case, "cfl above 1 with allow_unstable")
        call check(suite, case%time%allow_unstable .and. abs(case%time%cfl - 2.0_wp) < tol, &
            "allow_unstable and cfl resolved")
        call expect_error(suite, case_text(time='"time": {"tend": 0.1, "dt": 0.01}'), &
            [character(len=60) :: "time.dt", "critical time step", "allow_unstable"], &
            "dt above critical names the override")
        call read_valid(suite, case_text(time='"time": {"tend": 0.1, "dt": 0.01, '// &
            '"allow_unstable": true}'), case, "dt above critical with allow_unstable")
        call expect_error(suite, case_text(time='"time": {"tend": 0.1, "allow_unstable": 1}'), &
            [character(len=60) :: "time.allow_unstable"], "allow_unstable must be a boolean")
    end subroutine check_neo_hookean_and_unstable

end program test_mpm_case
