!> Helpers of the case-reader tests (test_mpm_case, test_mpm_case_errors): the pieces of a
!> small valid 2D case, cases built from them, reading a case that must be valid or must fail
!> with a given message, and the values of a material's law.
module mpm_testing_case
    use mpm_kinds, only: wp
    use mpm_error, only: error_type, exit_input
    use mpm_case, only: case_type, read_case_string, material_spec_type
    use mpm_strength, only: strength_type
    use mpm_elastic_solid, only: elastic_solid_type
    use mpm_material_mohr_coulomb, only: mohr_coulomb_material_type
    use mpm_material_drucker_prager, only: drucker_prager_material_type
    use mpm_material_newtonian, only: newtonian_material_type
    use mpm_testing, only: test_suite_type, check, check_contains
    implicit none
    private
    public :: domain_2d, materials_1, materials_2, bodies_1, time_1, tol, degree, elastic_part
    public :: case_text, soil_case, faces_case, read_valid, expect_error, write_text, delete_file
    public :: young_of, poisson_of, strength_of, cone_of, fluid_of

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
    real(wp), parameter :: tol = 10*epsilon(1.0_wp)
        !! values pass through one decimal-to-binary conversion: round-off only
    real(wp), parameter :: degree = acos(-1.0_wp)/180.0_wp
        !! one degree [rad]; an angle read in degrees is stored as degrees * (pi / 180), so it
        !! matches within a few ulps (tol relative to the angle)
    character(len=*), parameter :: elastic_part = '"E": 1e7, "nu": 0.3, "rho": 1800'
        !! elastic parameters of the soil materials of the plasticity tests

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

    !> The default case with one material "soil" made of the given keys (all but the name).
    function soil_case(keys) result(text)
        character(len=*), intent(in) :: keys
        character(len=:), allocatable :: text

        text = case_text(materials='"materials": [{"name": "soil", '//keys//"}]")
    end function soil_case

    !> The default case with the given domain.boundaries object.
    function faces_case(faces) result(text)
        character(len=*), intent(in) :: faces
        character(len=:), allocatable :: text

        text = case_text(domain='"domain": {"nx": 4, "ny": 2, "dx": 0.1, "boundaries": ' &
            //faces//"}")
    end function faces_case

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
    subroutine read_valid(suite, text, case, what)
        type(test_suite_type), intent(inout) :: suite
            !! the suite that counts the check
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
    subroutine expect_error(suite, text, parts, what, source)
        type(test_suite_type), intent(inout) :: suite
            !! the suite that counts the checks
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

    !> Young's modulus of a material's law, 0 when it is not an elastic solid [Pa].
    real(wp) function young_of(mat)
        type(material_spec_type), intent(in) :: mat
        select type (law => mat%law)
        class is (elastic_solid_type)
            young_of = law%young
        class default
            young_of = 0.0_wp
        end select
    end function young_of

    !> Poisson's ratio of a material's law, -1 when it is not an elastic solid [-].
    real(wp) function poisson_of(mat)
        type(material_spec_type), intent(in) :: mat
        select type (law => mat%law)
        class is (elastic_solid_type)
            poisson_of = law%poisson
        class default
            poisson_of = -1.0_wp
        end select
    end function poisson_of

    !> Strength of a Mohr-Coulomb or Drucker-Prager material (defaults for any other).
    type(strength_type) function strength_of(mat)
        type(material_spec_type), intent(in) :: mat
        select type (law => mat%law)
        type is (mohr_coulomb_material_type)
            strength_of = law%strength
        type is (drucker_prager_material_type)
            strength_of = law%strength
        class default
            strength_of = strength_type()
        end select
    end function strength_of

    !> Cone of a Drucker-Prager material, 0 for any other.
    integer function cone_of(mat)
        type(material_spec_type), intent(in) :: mat
        select type (law => mat%law)
        type is (drucker_prager_material_type)
            cone_of = law%cone
        class default
            cone_of = 0
        end select
    end function cone_of

    !> Viscosity (which = 1) [Pa s] or bulk modulus (2) [Pa] of a Newtonian fluid, -1 for
    !> any other material.
    real(wp) function fluid_of(mat, which)
        type(material_spec_type), intent(in) :: mat
        integer, intent(in) :: which
        select type (law => mat%law)
        type is (newtonian_material_type)
            fluid_of = merge(law%viscosity, law%bulk_modulus, which == 1)
        class default
            fluid_of = -1.0_wp
        end select
    end function fluid_of

end module mpm_testing_case
