!> Case reader: valid 2D and 3D cases resolve every value and default; every class of input
!> error gives one message (code exit_input) that names the key path, the bad value and what
!> is allowed; body particle counts agree with a brute-force count of the placement rule.
program test_mpm_case
    use mpm_kinds, only: wp
    use mpm_error, only: error_type, exit_input
    use mpm_case, only: case_type, read_case_file, read_case_string, case_summary, &
        critical_time_step, p_wave_speed, bc_free, bc_sliding, bc_fixed, scheme_musl, &
        scheme_usl, shape_cpgimp, shape_linear, damping_none, damping_local, dist_regular, &
        dist_random, field_position, field_velocity, field_stress
    use mpm_testing, only: test_suite_type, new_suite, check, check_close, check_contains, finish
    implicit none

    ! Pieces of a small valid 2D case: 4 x 2 cells of 0.1 m, one body of 2 x 1 cells.
    ! With E = 1e6 Pa, nu = 0, rho = 1000 kg/m3: c_p = sqrt(E/rho) = 31.6227766 m/s and the
    ! critical time step is dx/c_p = 0.00316227766 s.
    character(len=*), parameter :: domain_2d = '"domain": {"nx": 4, "ny": 2, "dx": 0.1}'
    character(len=*), parameter :: materials_1 = '"materials": [{"name": "soil", ' &
        //'"type": "linear_elastic", "E": 1e6, "nu": 0.0, "rho": 1000}]'
    character(len=*), parameter :: materials_2 = '"materials": [{"name": "soil", ' &
        //'"type": "linear_elastic", "E": 1e6, "nu": 0.0, "rho": 1000}, {"name": "rock", ' &
        //'"type": "elastic", "E": 1e9, "nu": 0.25, "rho": 2500}]'
    character(len=*), parameter :: bodies_1 = '"bodies": [{"name": "block", "material": ' &
        //'"soil", "min": [0, 0], "max": [0.2, 0.1]}]'
    character(len=*), parameter :: time_1 = '"time": {"tend": 0.1}'
    character(len=*), parameter :: state_file = "test_mpm_case_state.tmp"
    character(len=*), parameter :: case_file = "test_mpm_case_tmp.json"
    real(wp), parameter :: tol = 10*epsilon(1.0_wp)
        !! values pass through one decimal-to-binary conversion: round-off only

    type(test_suite_type) :: suite

    call new_suite(suite, "mpm_case")
    call write_text(state_file, "not a real state file: only its existence is checked")
    call test_valid_2d()
    call test_valid_3d()
    call test_manual_keys()
    call test_read_file()
    call test_particle_counts()
    call test_summary()
    call test_key_errors()
    call test_value_errors()
    call test_body_errors()
    call test_time_errors()
    call test_section_errors()
    call test_document_errors()
    call delete_file(state_file)
    call delete_file(case_file)
    call finish(suite)

contains

    !> A 2D case made of the default pieces; a piece given as "" is left out.
    function case_text(domain, materials, bodies, time, extra) result(text)
        character(len=*), intent(in), optional :: domain, materials, bodies, time, extra
        character(len=:), allocatable :: text

        text = "{"//piece(domain, domain_2d)
        text = text//piece(materials, materials_1)
        text = text//piece(bodies, bodies_1)
        text = text//piece(time, time_1)
        if (present(extra)) text = text//piece(extra, "")
        if (text(len(text):len(text)) == ",") text = text(1:len(text) - 1)
        text = text//"}"
    end function case_text

    !> The given piece (or the default) followed by a comma; nothing for "".
    function piece(given, default) result(text)
        character(len=*), intent(in), optional :: given
        character(len=*), intent(in) :: default
        character(len=:), allocatable :: text

        text = default
        if (present(given)) text = given
        if (len(text) > 0) text = text//","
    end function piece

    !> Read a case that must be valid.
    subroutine read_valid(text, case, what)
        character(len=*), intent(in) :: text
        type(case_type), intent(out) :: case
        character(len=*), intent(in) :: what

        type(error_type), allocatable :: error

        call read_case_string(text, case, error)
        if (allocated(error)) then
            call check(suite, .false., what//": unexpected error: "//error%message)
        else
            call check(suite, .true., what)
        end if
    end subroutine read_valid

    !> Read a case that must fail with exit_input and a message holding every part.
    subroutine expect_error(text, parts, what, source)
        character(len=*), intent(in) :: text
        character(len=*), intent(in) :: parts(:)
        character(len=*), intent(in) :: what
        character(len=*), intent(in), optional :: source

        type(case_type) :: case
        type(error_type), allocatable :: error
        integer :: i

        call read_case_string(text, case, error, source)
        if (.not. allocated(error)) then
            call check(suite, .false., what//": no error reported")
            return
        end if
        call check(suite, error%code == exit_input, what//": error code is exit_input")
        if (present(source)) then
            call check_contains(suite, error%message, source//": ", what//": file name first")
        else
            call check_contains(suite, error%message, "<string>: ", what//": source first")
        end if
        do i = 1, size(parts)
            call check_contains(suite, error%message, trim(parts(i)), what)
        end do
    end subroutine expect_error

    subroutine test_valid_2d()
        type(case_type) :: case

        call read_valid('{"name": "column", "domain": {"nx": 4, "ny": 2, "dx": 0.1, ' &
            //'"boundaries": {"xmin": "fixed", "xmax": "Sliding"}}, '//materials_1//", " &
            //'"bodies": [{"material": "soil", "min": [0, 0], "max": [0.2, 0.1], ' &
            //'"velocity": [1, 0]}], "gravity": [0, -9.81], ' &
            //'"solver": {"scheme": "musl", "shape_function": "GIMP"}, '//time_1//"}", &
            case, "valid 2D case")
        if (.not. allocated(case%bodies)) return
        call check(suite, case%dim == 2, "2D: dimension 2 without nz")
        call check(suite, all(case%ncells == [4, 2, 1]), "2D: ncells with nz = 1")
        call check_close(suite, case%dx, 0.1_wp, tol, "2D: dx")
        call check(suite, all(case%origin == 0.0_wp), "2D: origin defaults to zero")
        call check(suite, case%bc(1, 1) == bc_fixed .and. case%bc(2, 1) == bc_sliding, &
            "2D: x boundaries (any case)")
        call check(suite, all(case%bc(:, 2:3) == bc_free), "2D: other faces free")
        call check(suite, case%ppc == 2 .and. case%distribution == dist_regular, &
            "2D: particles default to ppc 2, regular")
        call check(suite, case%materials(1)%name == "soil" .and. &
            case%materials(1)%type == "linear_elastic", "2D: material name and type")
        call check_close(suite, case%materials(1)%young, 1.0e6_wp, tol*1.0e6_wp, "2D: E")
        call check_close(suite, case%materials(1)%density, 1000.0_wp, tol*1000, "2D: rho")
        call check(suite, case%bodies(1)%name == "body1", "2D: default body name")
        call check(suite, case%bodies(1)%material == 1, "2D: body material index")
        call check_close(suite, case%bodies(1)%xmax(1), 0.2_wp, tol, "2D: body max x")
        call check_close(suite, case%bodies(1)%velocity(1), 1.0_wp, tol, "2D: body velocity")
        call check_close(suite, case%gravity(2), -9.81_wp, tol*10, "2D: gravity y")
        call check(suite, case%scheme == scheme_musl, "2D: scheme 'musl' is MUSL")
        call check(suite, case%shape == shape_cpgimp, "2D: 'GIMP' is cpgimp")
        call check_close(suite, case%tend, 0.1_wp, tol, "2D: tend")
        call check(suite, case%dt == 0.0_wp, "2D: no fixed dt")
        call check_close(suite, case%cfl, 0.5_wp, 0.0_wp, "2D: cfl defaults to 0.5")
        call check(suite, case%damping == damping_none, "2D: no damping by default")
        call check_close(suite, case%output_interval, 0.1_wp/20, tol, "2D: interval tend/20")
        call check_close(suite, case%history_interval, 0.1_wp/200, tol, &
            "2D: history interval is interval/10")
        call check(suite, case%output_dir == "outputs/column", "2D: output folder")
        call check(suite, all(case%output_fields), "2D: all fields by default")
        call check(suite, .not. case%output_grid .and. .not. case%overwrite, &
            "2D: no grid output, no overwrite")
        call check(suite, case%save_state == "" .and. case%load_state == "", "2D: no states")
        call check(suite, case%contact_type == "none", "2D: contact none")
        call check(suite, case%file == "<string>", "2D: file of a string case")
        call check_close(suite, case%progress_seconds, 2.0_wp, 0.0_wp, "2D: progress 2 s")
        call check_close(suite, critical_time_step(case), 0.1_wp/(sqrt(1.0e3_wp) + 1), &
            1.0e-12_wp, "2D: critical step dx/(c_p + |v|)")
        call read_valid(case_text(), case, "default pieces")
        call check(suite, case%name == "case", "name of a case without source is 'case'")
    end subroutine test_valid_2d

    subroutine test_valid_3d()
        type(case_type) :: case

        call read_valid('{"name": "cube-3d.v1", "domain": {"nx": 2, "ny": 3, "nz": 4, ' &
            //'"dx": 0.5, "origin": [1, 2, 3], "boundaries": {"zmin": "fixed"}}, ' &
            //'"particles": {"ppc": 3, "distribution": "random", "seed": 7}, ' &
            //materials_2//', "bodies": [{"name": "b", "material": "rock", ' &
            //'"min": [1, 2, 3], "max": [2, 3.5, 5]}], "gravity": [0, 0, -9.81], ' &
            //'"solver": {"scheme": "USL", "shape_function": "linear"}, ' &
            //'"time": {"tend": 1, "dt": 1e-5}, "damping": {"type": "local", "value": 0.05}, ' &
            //'"output": {"interval": 0, "fields": ["velocity", "stress"], "grid": true, ' &
            //'"directory": "out/cube", "overwrite": true}, "progress": {"interval": 0.5}, ' &
            //'"save_state": "out/cube/state.h5"}', case, "valid 3D case")
        if (.not. allocated(case%bodies)) return
        call check(suite, case%dim == 3, "3D: dimension 3 from nz")
        call check(suite, all(case%ncells == [2, 3, 4]), "3D: ncells")
        call check(suite, all(abs(case%origin - [1, 2, 3]) <= tol*3), "3D: origin")
        call check(suite, case%bc(1, 3) == bc_fixed .and. case%bc(2, 3) == bc_free, &
            "3D: z faces")
        call check(suite, case%ppc == 3 .and. case%distribution == dist_random .and. &
            case%seed == 7, "3D: random particles with seed")
        call check(suite, case%materials(2)%type == "linear_elastic", &
            "3D: 'elastic' resolves to linear_elastic")
        call check_close(suite, case%materials(2)%poisson, 0.25_wp, tol, "3D: nu")
        call check(suite, case%bodies(1)%material == 2, "3D: body uses material 2")
        call check(suite, case%scheme == scheme_usl .and. case%shape == shape_linear, &
            "3D: scheme and shape")
        call check_close(suite, case%dt, 1.0e-5_wp, tol*1.0e-5_wp, "3D: fixed dt")
        call check(suite, case%damping == damping_local, "3D: local damping")
        call check_close(suite, case%damping_value, 0.05_wp, tol, "3D: damping alpha")
        call check(suite, case%output_interval == 0.0_wp .and. case%history_interval == 0.0_wp, &
            "3D: interval 0 gives history interval 0")
        call check(suite, case%output_fields(field_position) .and. &
            case%output_fields(field_velocity) .and. case%output_fields(field_stress) .and. &
            count(case%output_fields) == 3, "3D: listed fields plus position")
        call check(suite, case%output_grid .and. case%overwrite, "3D: grid and overwrite")
        call check(suite, case%output_dir == "out/cube", "3D: output directory")
        call check_close(suite, case%progress_seconds, 0.5_wp, 0.0_wp, "3D: progress")
        call check(suite, case%save_state == "out/cube/state.h5", "3D: save_state")
        call check(suite, case%name == "cube-3d.v1", "3D: name with '-' and '.'")
    end subroutine test_valid_3d

    !> Every key of the user manual is known: domain.nx/ny/nz/dx, particles.ppc/distribution,
    !> materials[].name/type/E/nu/rho, contact.type/mu/file, time.dt/tend,
    !> damping.type/value, save_state, load_state.
    subroutine test_manual_keys()
        type(case_type) :: case
        type(error_type), allocatable :: error

        call read_valid('{"dimension": 3, "domain": {"nx": 2, "ny": 2, "nz": 2, "dx": 1}, ' &
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
        call check(suite, case%output_dir == "outputs/test_mpm_case_tmp", "default output dir")

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
            call read_valid(case_text(bodies='"bodies": [{"name": "box", "material": "soil", ' &
                //trim(boxes(b))//"}]"), case, "count box "//trim(boxes(b)))
            if (.not. allocated(case%bodies)) cycle
            do d = 1, 2
                axis_count(d) = 0
                do i = 0, case%ncells(d) - 1
                    do k = 1, case%ppc
                        x = (i + (k - 0.5_wp)/case%ppc)*case%dx
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

        call read_valid(case_text(extra='"damping": {"type": "local", "value": 0.05}'), case, &
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
    end subroutine test_summary

    subroutine test_key_errors()
        call expect_error(case_text(extra='"nmae": "x"'), &
            [character(len=200) :: "unknown key 'nmae'", "did you mean 'name'?"], &
            "unknown top-level key")
        call expect_error(case_text(domain='"domain": {"nx": 4, "ny": 2, "dx": 0.1, ' &
            //'"boundaries": {"xmn": "fixed"}}'), [character(len=200) :: &
            "unknown key 'domain.boundaries.xmn'", "did you mean 'xmin'?"], "nested unknown key")
        call expect_error(case_text(extra='"completely_unrelated": 1'), [character(len=200) :: &
            "unknown key 'completely_unrelated'", "the keys allowed in the top level are:", &
            "domain, particles, materials"], "unknown key far from any key")
        call expect_error(case_text(materials='"materials": [{"name": "soil", "type": ' &
            //'"elastic", "e": 1e6, "nu": 0, "rho": 1000}]'), [character(len=200) :: &
            "unknown key 'materials[1].e'", "did you mean 'E'? (keys are case-sensitive)"], &
            "key in the wrong case")
        call expect_error(case_text(domain='"domain": {"nx": 4, "ny": 2, "dx": 0.1, ' &
            //'"dx": 0.2}'), [character(len=200) :: "duplicate key 'domain.dx'"], "duplicate key")
        call expect_error(case_text(domain='"domain": {"nx": 4, "ny": 2, "dx": "0.1"}'), &
            [character(len=200) :: "domain.dx has the wrong type", "expected a number > 0 [m]", &
            'found a string ("0.1")'], "wrong type")
        call expect_error(case_text(domain='"domain": {"nx": 4, "ny": 2}'), &
            [character(len=200) :: "missing required key 'domain.dx' (a number > 0 [m])"], &
            "missing required key")
        call expect_error(case_text(time='"time": {}'), &
            [character(len=200) :: "missing required key 'time.tend'"], "missing tend")
    end subroutine test_key_errors

    subroutine test_value_errors()
        type(case_type) :: case

        call expect_error(case_text(materials='"materials": [{"name": "soil", "type": ' &
            //'"elastic", "E": 0, "nu": 0, "rho": 1000}]'), [character(len=200) :: &
            "materials[1].E = 0 is out of range: must be > 0 [Pa]"], "E = 0")
        call expect_error(case_text(materials='"materials": [{"name": "soil", "type": ' &
            //'"elastic", "E": -5e6, "nu": 0, "rho": 1000}]'), [character(len=200) :: &
            "materials[1].E = -5000000 is out of range: must be > 0 [Pa]"], "E < 0")
        call expect_error(case_text(materials='"materials": [{"name": "soil", "type": ' &
            //'"elastic", "E": 1e6, "nu": 0.5, "rho": 1000}]'), [character(len=200) :: &
            "materials[1].nu = 0.5 is out of range: must be >= 0 and < 0.5"], "nu = 0.5")
        call expect_error(case_text(materials='"materials": [{"name": "soil", "type": ' &
            //'"elastic", "E": 1e6, "nu": -0.1, "rho": 1000}]'), [character(len=200) :: &
            "materials[1].nu = -0.1 is out of range: must be >= 0 and < 0.5"], "nu < 0")
        call expect_error(case_text(materials='"materials": [{"name": "soil", "type": ' &
            //'"elastic", "E": 1e6, "nu": 0.2, "rho": 0}]'), [character(len=200) :: &
            "materials[1].rho = 0 is out of range: must be > 0 [kg/m3]"], "rho = 0")
        call expect_error(case_text(materials='"materials": [{"name": "soil", "type": ' &
            //'"plastic", "E": 1e6, "nu": 0.2, "rho": 1}]'), [character(len=200) :: &
            'materials[1].type = "plastic" is not allowed', '"linear_elastic", "elastic"'], &
            "unknown material type")
        call expect_error(case_text(domain='"domain": {"nx": 4, "ny": 2, "dx": -0.1}'), &
            [character(len=200) :: &
            "inputs/bad.json: domain.dx = -0.1 is out of range: must be > 0 [m]"], "dx < 0", &
            source="inputs/bad.json")
        call expect_error(case_text(domain='"domain": {"nx": 4, "ny": 2, "dx": 0}'), &
            [character(len=200) :: "domain.dx = 0 is out of range: must be > 0 [m]"], "dx = 0")
        call expect_error(case_text(domain='"domain": {"nx": 2.5, "ny": 2, "dx": 0.1}'), &
            [character(len=200) :: "domain.nx = 2.5 is not a whole number"], "nx = 2.5")
        call expect_error(case_text(domain='"domain": {"nx": 100000, "ny": 100000, "dx": 1}'), &
            [character(len=200) :: "100000 x 100000 cells", "nodes, more than the 2147483647"], &
            "too many nodes")
        call expect_error(case_text(extra='"particles": {"ppc": 0}'), [character(len=200) :: &
            "particles.ppc = 0 is out of range: must be an integer >= 1 and <= 10"], "ppc = 0")
        call expect_error(case_text(extra='"particles": {"ppc": 1.5}'), [character(len=200) :: &
            "particles.ppc = 1.5 is not a whole number: must be an integer >= 1 and <= 10"], &
            "ppc = 1.5")
        call read_valid(case_text(extra='"particles": {"ppc": 3.0}'), case, "ppc = 3.0")
        call check(suite, case%ppc == 3, "ppc = 3.0 is the integer 3")
        call expect_error(case_text(extra='"particles": {"seed": 3}'), [character(len=200) :: &
            "particles.seed only applies to particles.distribution"], "seed without random")
        call expect_error(case_text(extra='"name": "my case"'), [character(len=200) :: &
            'name = "my case" is not allowed', "letters, digits"], "name with a blank")
        call expect_error(case_text(extra='"gravity": [0, -9.81, 0]'), [character(len=200) :: &
            "gravity must have 2 numbers", "found 3"], "gravity of the wrong length")
        call expect_error(case_text(extra='"gravity": [0, "down"]'), [character(len=200) :: &
            "gravity[2] has the wrong type: expected a number"], "gravity item type")
        call expect_error(case_text(extra='"solver": {"scheme": "RK4"}'), [character(len=200) :: &
            'solver.scheme = "RK4" is not allowed', '"USF", "USL", "MUSL"'], "unknown scheme")
        call expect_error(case_text(extra='"output": {"fields": ["velocity", "pressure"]}'), &
            [character(len=200) :: 'output.fields[2] = "pressure" is not a field', &
            '"position", "displacement"'], "unknown output field")
        call expect_error(case_text(extra='"output": {"fields": ["mass", "mass"]}'), &
            [character(len=200) :: 'output.fields[2] = "mass" is listed twice'], "field twice")
        call expect_error(case_text(extra='"output": {"grid": 1}'), [character(len=200) :: &
            "output.grid has the wrong type: expected true or false, found a number (1)"], &
            "boolean expected")
        call expect_error(case_text(extra='"save_state": ""'), [character(len=200) :: &
            'save_state = "" is not allowed: must be a non-empty string'], "empty save_state")
    end subroutine test_value_errors

    subroutine test_body_errors()
        type(case_type) :: case

        call expect_error(case_text(bodies='"bodies": [{"name": "block", "material": "soil", ' &
            //'"min": [0, 0], "max": [0.5, 0.1]}]'), [character(len=200) :: 'bodies[1] "block"', &
            "corner max = (0.5, 0.1)", "outside the domain [0, 0.4] x [0, 0.2] [m]"], &
            "body outside the domain")
        call expect_error(case_text(bodies='"bodies": [{"material": "soil", ' &
            //'"min": [0, -0.1], "max": [0.1, 0.1]}]'), [character(len=200) :: &
            'bodies[1] "body1": corner min = (0, -0.1)'], "body below the domain")
        call expect_error(case_text(bodies='"bodies": [{"name": "a", "material": "soil", ' &
            //'"min": [0, 0], "max": [0.2, 0.1]}, {"name": "b", "material": "soil", ' &
            //'"min": [0.1, 0.05], "max": [0.3, 0.2]}]'), [character(len=200) :: &
            'bodies[2] "b" overlaps bodies[1] "a"', "[0.1, 0.3] x [0.05, 0.2]"], &
            "overlapping bodies")
        call read_valid(case_text(bodies='"bodies": [{"name": "a", "material": "soil", ' &
            //'"min": [0, 0], "max": [0.2, 0.1]}, {"name": "b", "material": "soil", ' &
            //'"min": [0.2, 0], "max": [0.4, 0.3e-0]}]', &
            domain='"domain": {"nx": 4, "ny": 3, "dx": 0.1}'), case, &
            "bodies that touch do not overlap")
        call expect_error(case_text(materials=materials_2, bodies='"bodies": [{"name": "a", ' &
            //'"material": "sand", "min": [0, 0], "max": [0.2, 0.1]}]'), [character(len=200) :: &
            'bodies[1].material = "sand" is not a material', '"soil", "rock"'], &
            "unknown material name")
        call expect_error(case_text(bodies='"bodies": [{"name": "thin", "material": "soil", ' &
            //'"min": [0, 0], "max": [0.02, 0.1]}]'), [character(len=200) :: &
            'bodies[1] "thin": the box [0, 0.02] x [0, 0.1] [m] holds no particle'], &
            "body without particles")
        call expect_error(case_text(bodies='"bodies": [{"name": "flat", "material": "soil", ' &
            //'"min": [0, 0.1], "max": [0.2, 0.1]}]'), [character(len=200) :: &
            'bodies[1] "flat": min[2] = 0.1 must be below max[2] = 0.1'], "empty box")
        call expect_error(case_text(bodies='"bodies": [{"name": "a", "material": "soil", ' &
            //'"min": [0, 0], "max": [0.1, 0.1]}, {"name": "a", "material": "soil", ' &
            //'"min": [0.2, 0], "max": [0.3, 0.1]}]'), [character(len=200) :: &
            'bodies[2].name = "a" is already the name of bodies[1]'], "body names unique")
        call expect_error(case_text(materials='"materials": [{"name": "x", "type": ' &
            //'"elastic", "E": 1, "nu": 0, "rho": 1}, {"name": "x", "type": "elastic", ' &
            //'"E": 1, "nu": 0, "rho": 1}]'), [character(len=200) :: &
            'materials[2].name = "x" is already the name of materials[1]'], &
            "material names unique")
        call expect_error(case_text(materials='"materials": []'), [character(len=200) :: &
            "materials is an empty array"], "no material")
        call expect_error(case_text(bodies=""), [character(len=200) :: &
            "missing required key 'bodies'", "load_state"], "no bodies and no load_state")
        call expect_error(case_text(extra='"load_state": "no/such/state.h5"'), &
            [character(len=200) :: "load_state: file 'no/such/state.h5' not found"], &
            "missing load_state file")
        call expect_error(case_text(extra='"load_state": "'//state_file//'"'), &
            [character(len=200) :: "bodies cannot be given together with load_state", &
            "the particles come from the state file"], "bodies with load_state")
    end subroutine test_body_errors

    subroutine test_time_errors()
        type(case_type) :: case

        ! critical step dx/c_p = 0.1/31.6227766 = 0.00316228 s (6 digits)
        call expect_error(case_text(time='"time": {"tend": 1, "dt": 0.01}'), &
            [character(len=200) :: "time.dt = 0.01 s is above the critical time step " &
            //"0.00316228 s of this case (dx / max(c_p + |v|)); use a smaller dt or set " &
            //"time.cfl instead"], "dt above the critical step")
        call read_valid(case_text(time='"time": {"tend": 1, "dt": 0.003}'), case, &
            "dt below the critical step")
        call check_close(suite, critical_time_step(case), &
            0.1_wp/p_wave_speed(case%materials(1)), 1.0e-15_wp, "critical step of the case")
        call expect_error(case_text(time='"time": {"tend": 1, "dt": 1e-3, "cfl": 0.5}'), &
            [character(len=200) :: "time.dt and time.cfl are alternatives"], "dt and cfl")
        call expect_error(case_text(time='"time": {"tend": 1, "cfl": 1.5}'), &
            [character(len=200) :: "time.cfl = 1.5 is out of range: must be > 0 and <= 1"], &
            "cfl > 1")
        call expect_error(case_text(time='"time": {"tend": 0}'), [character(len=200) :: &
            "time.tend = 0 is out of range: must be > 0 [s]"], "tend = 0")
        call expect_error(case_text(time='"time": {"tend": 1e9}'), [character(len=200) :: &
            "time.tend = 1e9 s needs more than 1e9 steps"], "too many steps")
        ! with load_state the critical step comes from the fastest material: rock has
        ! c_p = sqrt((K + 4G/3)/rho) = sqrt(1.2e9/2500) = 692.82 m/s, dx/c_p = 0.000144338 s
        call expect_error("{"//domain_2d//", "//materials_2//', "load_state": "' &
            //state_file//'", "time": {"tend": 1, "dt": 2e-4}}', [character(len=200) :: &
            "time.dt = 0.0002 s is above the critical time step 0.000144338 s"], &
            "dt with load_state: fastest material")
    end subroutine test_time_errors

    subroutine test_section_errors()
        call expect_error(case_text(extra='"contact": {"type": "terrain_stl", "mu": 0.4, ' &
            //'"file": "data/terrain.stl"}'), [character(len=200) :: "contact.type = " &
            //'"terrain_stl": STL terrain contact is not available in this version of ' &
            //'mpm-geo; remove the contact section or set "type": "none"'], &
            "terrain_stl refused")
        call expect_error(case_text(extra='"contact": {"type": "none", "mu": 0.4}'), &
            [character(len=200) :: "contact.mu only applies", "terrain_stl"], "mu without STL")
        call expect_error(case_text(domain='"domain": {"nx": 4, "ny": 2, "nz": 2, "dx": 0.1}', &
            extra='"dimension": 2'), [character(len=200) :: &
            "domain.nz is given but dimension = 2"], "nz with dimension 2")
        call expect_error(case_text(extra='"dimension": 3'), [character(len=200) :: &
            "missing required key 'domain.nz'", "dimension = 3"], "dimension 3 without nz")
        call expect_error(case_text(extra='"dimension": 4'), [character(len=200) :: &
            "dimension = 4 is out of range: must be an integer >= 2 and <= 3"], "dimension 4")
        call expect_error(case_text(domain='"domain": {"nx": 4, "ny": 2, "dx": 0.1, ' &
            //'"boundaries": {"zmin": "fixed"}}'), [character(len=200) :: &
            "domain.boundaries.zmin is not allowed in a 2D case"], "z face in 2D")
        call expect_error(case_text(domain='"domain": {"nx": 4, "ny": 2, "dx": 0.1, ' &
            //'"boundaries": {"xmin": "clamped"}}'), [character(len=200) :: &
            'domain.boundaries.xmin = "clamped" is not allowed', &
            'must be one of "free", "sliding", "fixed"'], "unknown boundary condition")
        call expect_error(case_text(extra='"damping": {"type": "none", "value": 0.1}'), &
            [character(len=200) :: 'damping.value only applies to damping.type = "local"'], &
            "damping value without local")
        call expect_error(case_text(extra='"damping": {"type": "local"}'), &
            [character(len=200) :: "missing required key 'damping.value'"], "local no value")
        call expect_error(case_text(extra='"damping": {"type": "local", "value": 1}'), &
            [character(len=200) :: "damping.value = 1 is out of range: must be >= 0 and < 1"], &
            "damping value 1")
        call expect_error(case_text(extra='"progress": {"interval": 0}'), [character(len=200) :: &
            "progress.interval = 0 is out of range: must be > 0 [s]"], "progress 0")
        call expect_error(case_text(extra='"output": {"interval": -1}'), [character(len=200) :: &
            "output.interval = -1 is out of range: must be >= 0 [s]"], "output interval < 0")
    end subroutine test_section_errors

    subroutine test_document_errors()
        character(len=*), parameter :: nl = new_line("a")

        ! the comma after line 3 is missing: the parser stops at the start of line 4
        call expect_error("{"//nl//domain_2d//","//nl//materials_1//nl//bodies_1//","//nl &
            //time_1//"}", [character(len=200) :: "invalid JSON at line 4"], "JSON syntax error")
        call expect_error("", [character(len=200) :: "empty"], "empty text")
        call expect_error("   ", [character(len=200) :: "empty"], "blank text")
        call expect_error("[1, 2]", [character(len=200) :: &
            "the top level must be a JSON object", "found an array"], "top-level array")
        call expect_error("42", [character(len=200) :: &
            "the top level must be a JSON object", "found a number (42)"], "top-level number")
        call expect_error(case_text(domain='"domain": [4, 2]'), [character(len=200) :: &
            "domain has the wrong type: expected an object, found an array"], "domain array")
        call expect_error(case_text(materials='"materials": [1]'), [character(len=200) :: &
            "materials[1] has the wrong type: expected an object"], "material not an object")
    end subroutine test_document_errors

    subroutine write_text(path, text)
        character(len=*), intent(in) :: path
        character(len=*), intent(in) :: text

        integer :: unit

        open (newunit=unit, file=path, status="replace", action="write")
        write (unit, "(a)") text
        close (unit)
    end subroutine write_text

    subroutine delete_file(path)
        character(len=*), intent(in) :: path

        integer :: unit, stat
        character(len=256) :: msg

        ! a missing file is fine: there is nothing to delete
        open (newunit=unit, file=path, status="old", iostat=stat, iomsg=msg)
        if (stat == 0) close (unit, status="delete")
    end subroutine delete_file

end program test_mpm_case
