!> Verification: bodies given as a list of particles (`bodies[i].particle_list`).
!>
!> A list holding exactly the particles a box body makes (their positions, volumes h^2 and the
!> box's material) gives the same run: after 100 steps under gravity on a fixed base, every
!> position, velocity and stress equals the box's bit for bit. A list with a material column
!> (by name and by position) and stress columns gives each particle its material, its mass
!> (density times volume), its size and its stress. Refused, with the file, the line and what
!> is wrong: a missing column, a position outside the domain, a volume <= 0, an unknown
!> material, a line with too few fields, some but not all stress columns, and the K0 initial
!> stress with a list.
program test_particle_list
    use mpm_kinds, only: wp
    use mpm_testing, only: test_suite_type, new_suite, check, check_close, finish
    use mpm_testing_case, only: expect_error
    use mpm_error, only: error_type
    use mpm_case, only: case_type, read_case_string
    use mpm_solver, only: simulation_type, new_simulation, advance, stable_time_step
    implicit none

    type(test_suite_type) :: suite
    character(len=*), parameter :: file = "test_particle_list.tmp.csv"
    character(len=*), parameter :: head = '{"domain": {"nx": 8, "ny": 8, "dx": 0.1, ' &
        //'"boundaries": {"ymin": "fixed"}}, "materials": [{"name": "soil", "type": ' &
        //'"linear_elastic", "E": 1e6, "nu": 0.3, "rho": 2000}, {"name": "rock", "type": ' &
        //'"linear_elastic", "E": 1e7, "nu": 0.25, "rho": 2600}], "gravity": [0, -9.81], ' &
        //'"time": {"tend": 1}, '

    call new_suite(suite, "particle_list")
    call same_as_box()
    call columns()
    call refused()
    call execute_command_line("rm -f "//file)
    call finish(suite)

contains

    subroutine write_lines(lines)
        character(len=*), intent(in) :: lines(:)
        integer :: unit, k

        open (newunit=unit, file=file, status="replace", action="write")
        do k = 1, size(lines)
            write (unit, "(a)") trim(lines(k))
        end do
        close (unit)
    end subroutine write_lines

    subroutine same_as_box()
        type(case_type) :: box_case, list_case
        type(simulation_type) :: box, list
        type(error_type), allocatable :: error
        integer :: i, j, unit, step
        real(wp) :: h

        ! the box [0.2, 0.6] x [0, 0.4], ppc 2: sites (i + 1/2) h, h = 0.05
        h = 0.05_wp
        open (newunit=unit, file=file, status="replace", action="write")
        write (unit, "(a)") "x, y, volume"
        do j = 0, 7
            do i = 4, 11
                write (unit, "(es25.17, ',', es25.17, ',', es25.17)") (i + 0.5_wp)*h, &
                    (j + 0.5_wp)*h, h*h
            end do
        end do
        close (unit)
        call read_case_string(head//'"bodies": [{"material": "soil", "min": [0.2, 0], "max": ' &
            //'[0.6, 0.4]}]}', box_case, error)
        call check(suite, .not. allocated(error), "box case reads")
        call read_case_string(head//'"bodies": [{"material": "soil", "particle_list": "'//file &
            //'"}]}', list_case, error)
        call check(suite, .not. allocated(error), "list case reads")
        if (allocated(error)) then
            print "(a)", error%message
            return
        end if
        call check(suite, list_case%bodies(1)%particles == 64, "64 particles listed")
        call new_simulation(box, box_case, error)
        call new_simulation(list, list_case, error)
        call check(suite, .not. allocated(error), "list simulation starts")
        if (allocated(error)) return
        do step = 1, 100
            call advance(box, stable_time_step(box), error)
            call advance(list, stable_time_step(list), error)
        end do
        call check(suite, box%particles%n == list%particles%n, "same particle count")
        call check(suite, all(box%particles%x == list%particles%x) .and. &
            all(box%particles%v == list%particles%v) .and. &
            all(box%particles%stress == list%particles%stress), &
            "100 steps: positions, velocities and stresses equal the box's bit for bit")
        call check(suite, any(box%particles%stress /= 0.0_wp), "(and the column is loaded)")
    end subroutine same_as_box

    subroutine columns()
        type(case_type) :: case
        type(simulation_type) :: sim
        type(error_type), allocatable :: error

        call write_lines([character(len=80) :: "material, volume, y, x, sxx, syy, szz, sxy", &
            "rock, 0.0004, 0.1, 0.1, -1, -2, -3, 4", "1, 0.0009, 0.3, 0.5, 0, 0, 0, 0", &
            "", "soil, 0.0001, 0.7, 0.75, 5, 6, 7, 8"])
        call read_case_string(head//'"bodies": [{"material": "soil", "particle_list": "'//file &
            //'", "velocity": [1, 0]}]}', case, error)
        call check(suite, .not. allocated(error), "list with materials and stresses reads")
        if (allocated(error)) then
            print "(a)", error%message
            return
        end if
        call new_simulation(sim, case, error)
        call check(suite, .not. allocated(error) .and. sim%particles%n == 3, "3 particles (a " &
            //"blank line skipped)")
        if (allocated(error)) return
        call check(suite, all(sim%particles%material == [2, 1, 1]), "materials by name and position")
        call check_close(suite, sim%particles%mass(1), 2600.0_wp*0.0004_wp, 1.0e-12_wp, &
            "mass = density x volume")
        call check_close(suite, sim%particles%lp0(1, 2), 0.015_wp, 1.0e-15_wp, &
            "size: half the side of the square of its volume")
        call check(suite, all(sim%particles%x(:, 1) == [0.1_wp, 0.1_wp]), "columns in any order")
        call check(suite, all(sim%particles%stress(:, 3) == [5.0_wp, 6.0_wp, 7.0_wp, 8.0_wp]), &
            "stresses from the columns")
        call check(suite, all(sim%particles%v(1, :) == 1.0_wp), "the body's velocity")
    end subroutine columns

    subroutine refused()
        character(len=:), allocatable :: text

        text = head//'"bodies": [{"material": "soil", "particle_list": "'//file//'"}]}'
        call write_lines([character(len=40) :: "x, volume", "0.1, 0.01"])
        call expect_error(suite, text, [character(len=200) :: "bodies[1].particle_list = " &
            //'"'//file//'": its header line', "must name the columns x, y and volume"], &
            "missing column")
        call write_lines([character(len=40) :: "x, y, volume", "0.1, 0.9, 0.01"])
        call expect_error(suite, text, [character(len=200) :: "line 2: the position (0.1, 0.9) " &
            //"m is outside the domain"], "outside the domain")
        call write_lines([character(len=40) :: "x, y, volume", "0.1, 0.1, 0.01", &
            "0.1, 0.2, 0"])
        call expect_error(suite, text, [character(len=200) :: "line 3: volume = 0 must be > 0"], &
            "zero volume")
        call write_lines([character(len=40) :: "x, y, volume, material", "0.1, 0.1, 0.01, sand"])
        call expect_error(suite, text, [character(len=200) :: "line 2: material 'sand' is not " &
            //"a material of this case", '"soil", "rock"'], "unknown material")
        call write_lines([character(len=40) :: "x, y, volume", "0.1, 0.1"])
        call expect_error(suite, text, [character(len=200) :: "line 2 has 2 fields, the header 3"], &
            "short line")
        call write_lines([character(len=40) :: "x, y, volume", "0.1, abc, 0.01"])
        call expect_error(suite, text, [character(len=200) :: "line 2, column 2: 'abc' is not a " &
            //"finite number"], "not a number")
        call write_lines([character(len=40) :: "x, y, volume, sxx", "0.1, 0.1, 0.01, 1"])
        call expect_error(suite, text, [character(len=200) :: "give all the stress columns " &
            //"sxx, syy, szz, sxy or none"], "some stresses")
        call write_lines([character(len=40) :: "x, y, volume, colour", "0.1, 0.1, 0.01, 1"])
        call expect_error(suite, text, [character(len=200) :: "unknown column 'colour'"], &
            "unknown column")
        call write_lines([character(len=40) :: "x, y, volume", "0.1, 0.1, 0.01"])
        call expect_error(suite, head//'"bodies": [{"material": "soil", "particle_list": "' &
            //file//'"}], "initial_stress": {"type": "k0"}}', [character(len=200) :: &
            'initial_stress.type = "k0" weighs the bodies filled on the lattice'], "k0 with a list")
        call expect_error(suite, head//'"bodies": [{"material": "soil", "particle_list": "' &
            //file//'", "min": [0, 0]}]}', [character(len=200) :: "a particle_list body " &
            //"takes its particles from the file; remove 'min'"], "list and box")
        call expect_error(suite, head//'"bodies": [{"material": "soil", "particle_list": ' &
            //'"no_such_list.csv"}]}', [character(len=200) :: 'bodies[1].particle_list = ' &
            //'"no_such_list.csv": no such file'], "missing file")
    end subroutine refused

end program test_particle_list
