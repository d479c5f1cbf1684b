!> The `initial_stress` key of a case: the stresses the particles start with.
!>
!> `"type": "k0"` is the geostatic state of a ground at rest under its own weight: at every
!> particle the vertical stress is the weight of the material above it up to the free surface
!> (per unit area, through every body it crosses), the horizontal stresses K0 times it, no
!> shear. K0 is `k0` when given, otherwise each material's own (`material_type%at_rest_ratio`:
!> 1 - sin(phi) for Mohr-Coulomb and Drucker-Prager after Jaky, nu / (1 - nu) for an elastic
!> solid, 1 for a fluid). The alternative is a damped first stage (inputs/geostatic_stage.json).
module mpm_case_initial_stress
    use mpm_kinds, only: wp
    use mpm_error, only: error_type
    use mpm_strings, only: fmt_vector
    use mpm_case_cursor, only: cursor_type
    use mpm_case_materials, only: material_spec_type
    implicit none
    private
    public :: initial_stress_section_type, read_initial_stress, initial_stress_keys
    public :: initial_none, initial_k0, initial_stress_names

    integer, parameter :: initial_none = 0
        !! the particles start unstressed (or with the stresses of load_state)
    integer, parameter :: initial_k0 = 1
        !! the geostatic stresses: vertical from the weight above, horizontal K0 times it
    character(len=*), parameter :: initial_stress_names(0:1) = [character(len=4) :: "none", &
        "k0"]
        !! name of each type in the case file
    character(len=*), parameter :: initial_stress_keys(*) = [character(len=4) :: "type", "k0"]
        !! keys of `initial_stress`
    real(wp), parameter :: k0_limit = 10.0_wp
        !! largest K0 accepted (exclusive): heavily overconsolidated clays reach about 3

    !> `initial_stress`: which initial stresses, and K0 per material.
    type :: initial_stress_section_type
        integer :: type = initial_none
            !! initial_none or initial_k0
        real(wp) :: k0 = -1.0_wp
            !! K0 given in the case (negative: each material's own)
        real(wp), allocatable :: k0_material(:)
            !! with initial_k0, the K0 of each material of the case (resolved)
    end type initial_stress_section_type

contains

    !> `initial_stress`: type and K0, checked against the gravity (along the last axis,
    !> downwards) and the start of the particles (bodies, not load_state).
    subroutine read_initial_stress(root, dim, gravity, materials, load_state, section, error)
        type(cursor_type), intent(in) :: root
            !! top-level object
        integer, intent(in) :: dim
            !! number of space dimensions
        real(wp), intent(in) :: gravity(3)
            !! gravity of the case [m/s2]
        type(material_spec_type), intent(in) :: materials(:)
            !! the materials
        character(len=*), intent(in) :: load_state
            !! state file the particles come from ("" for none)
        type(initial_stress_section_type), intent(inout) :: section
            !! the section
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        type(cursor_type) :: cur
        logical :: found
        integer :: i
        character(len=1), parameter :: axis_name(3) = ["x", "y", "z"]

        call root%get_section("initial_stress", initial_stress_keys, cur, error, found=found)
        if (allocated(error) .or. .not. found) return
        call cur%get_choice("type", initial_stress_names, [initial_none, initial_k0], &
            section%type, error, required=.true.)
        if (allocated(error)) return
        if (section%type /= initial_k0) then
            if (cur%has("k0")) call cur%fail(error, "initial_stress.k0 only applies to " &
                //'initial_stress.type = "k0"; remove it')
            return
        end if
        call cur%get_real("k0", section%k0, error, above=0.0_wp, below=k0_limit)
        if (allocated(error)) return
        if (len(load_state) > 0) then
            call cur%fail(error, 'initial_stress.type = "k0" cannot be used with load_state: ' &
                //"the particles and their stresses come from the state file '"//load_state &
                //"'; remove one of them")
            return
        end if
        if (.not. (gravity(dim) < 0.0_wp .and. all(gravity(1:dim - 1) == 0.0_wp))) then
            call cur%fail(error, 'initial_stress.type = "k0" needs gravity along -' &
                //axis_name(dim)//" (the vertical of a "//merge("2D", "3D", dim == 2) &
                //" case) and no other component; gravity = "//fmt_vector(gravity(1:dim)) &
                //" m/s2")
            return
        end if
        allocate (section%k0_material(size(materials)))
        do i = 1, size(materials)
            section%k0_material(i) = section%k0
            if (section%k0 < 0.0_wp) then
                section%k0_material(i) = 1.0_wp
                if (allocated(materials(i)%law)) section%k0_material(i) = &
                    materials(i)%law%at_rest_ratio()
            end if
        end do
    end subroutine read_initial_stress

end module mpm_case_initial_stress
